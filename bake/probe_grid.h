#pragma once
// Light probes (issue 38): a regular grid of points in the static scene, each holding the light
// arriving there from every direction, to light moving objects (Scene::dynamic_meshes) that
// the bake does not cover. bake/probes/ fills the grid; the viewer and the export read it.
//
// THE CONVENTION (docs/export.md, "Light probes"): a probe holds the L2 spherical-harmonic
// coefficients of the INCIDENT RADIANCE at its point,
//     c_lm = \int_{S^2} L(w) Y_lm(w) dw,   W/(sr m^2) per linear RGB channel,
// w the unit direction towards the source, in world axes (+Y up), the real SH basis in
// three.js's (and Sloan's "Stupid SH tricks") order and normalisation:
//     Y_00 = 0.282095,
//     Y_1-1 = 0.488603 y,  Y_10 = 0.488603 z,  Y_11 = 0.488603 x,
//     Y_2-2 = 1.092548 xy, Y_2-1 = 1.092548 yz, Y_20 = 0.315392 (3 z^2 - 1),
//     Y_21 = 1.092548 xz,  Y_22 = 0.546274 (x^2 - y^2).
// The irradiance at a surface with unit normal n (Ramamoorthi & Hanrahan 2001, the cosine
// lobe's SH weights A_0 = pi, A_1 = 2 pi / 3, A_2 = pi / 4):
//     E(n) = sum_lm A_l c_lm Y_lm(n),      W/m^2,
// so a Lambertian surface of albedo R reflects R E(n) / pi; in the stored-light convention of
// bake/bake_result.h its "baked term" is E(n) / pi. three.js's LightProbe takes c_lm as they
// are (its shader applies the A_l). A uniform field L gives c_00 = sqrt(4 pi) L and E = pi L.

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "bake/accel.h"
#include "bake/probe_grid_data.h"
#include "bake/scene.h"

namespace lb {

// Y_lm(w) for a unit w, in the order above.
std::array<float, kShCoefficients> sh_basis(vec3 w);
// E(n) in W/m^2 for a unit n, clamped at 0 (a truncated band can ring below 0 opposite a
// strong light).
vec3 sh_irradiance(const ShL2& sh, vec3 n);

// The probes lighting one moving object, blended at one point (its centre), as Unity's
// per-renderer probe blend: trilinear weights over the 8 probes around the point, leaving out
// invalid probes and probes the point cannot see (an occlusion ray through `accel`, the static
// scene: this is what keeps light from leaking through a wall between the object and a probe),
// renormalised. When none of the 8 remains, the ring around them is tried (the 4 x 4 x 4 block,
// then 6 x 6 x 6, ...), weighted by inverse squared distance; `ring` says which was used
// (-1: no valid visible probe at all, sh is 0). A point outside the grid blends the nearest
// cell's probes.
struct ProbeBlend {
  ShL2 sh{};
  int probes = 0;  // probes that took part
  int ring = -1;   // 0: the 8 around the point; r > 0: the (2r + 2)^3 block
};
ProbeBlend blend_probes(const ProbeGrid& grid, const Accel& accel, vec3 point);
// The same over a grid's layout whose probes are asked for as needed: `probe(index)` returns
// the probe's coefficients, or nullptr when it is invalid (a blend bakes only the few it reads).
ProbeBlend blend_probes(const ProbeGrid& layout, const Accel& accel, vec3 point,
                        const std::function<const ShL2*(size_t index)>& probe);

// The centre of a mesh's bounding box (where a moving object is blended).
vec3 mesh_centre(const Mesh& mesh);

}  // namespace lb
