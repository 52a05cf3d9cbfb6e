#pragma once
// The L1 band of baked light (issue 38, directional lightmaps): four RGB coefficients per texel
// from which a renderer takes the baked irradiance at any shading normal n (a bump or normal
// map's), not only at the surface's own normal n0.
//
// Convention (docs/export.md, "Directional maps"), world axes, W/(sr m^2) like every stored
// term (E/pi, before the reflectance, bake/bake_result.h):
//   L0 = E(n0) / pi                      the plain map, unchanged;
//   L1 = P (1/pi) \int L(w) w dw,        P = I - n0 n0^T (the tangent plane's projector);
//   s  in [0, 1]                         the direct term's share of L0;
//   E(n) / pi ~= max(0, L0 (1 - W (1 - n . n0)) + L1 . n),  W = (1 + s) / 2   the decode
//                                                             (decode_directional).
// (1/pi) \int L w dw is the irradiance vector over pi, i.e. the L1 spherical-harmonic
// coefficients of the incident radiance, L1_m = Y1 \int L w_m dw with Y1 = sqrt(3 / (4 pi)),
// times 1 / (pi Y1). Its component along n0 is E(n0)/pi, which the decode takes from L0 (the
// map as stitched and filled), so a surface without a bump map (n = n0) draws today's map
// exactly whatever s, and only the tangential part, the first-order change of E/pi as n tilts,
// is new. Beyond first order, (L0, L1) cannot tell light from one direction (E/pi follows the
// cosine law) from light from the whole sky above the plane (E/pi = L0 (1 + n . n0) / 2: what
// a tilted normal sees of a uniform hemisphere, the plane below being dark, as the reference
// takes it), so s says how much of L0 is which: the direct term's share (one direction per
// small source), the rest taken as the sky's. For light from one direction (s = 1, W = 1) the
// decode is its irradiance vector L0 n0 + L1 taken at n, the cosine law exactly, clamp
// included; for a uniform sky (s = 0, L1 = 0) it is L0 (1 + n . n0) / 2 exactly; for their sum
// it is exact wherever the sun is in front of n. Bumped surfaces therefore draw less light
// than the plain map (as they do in the reference), not the same.
//
// De-ringing: |L1_c| <= L0_c in each colour channel c; dering() scales L1_c down to that (a
// light more grazing than 45 degrees loses some of its directionality, and the decode is exact
// for one direction only within 45 degrees of n0). With it, an engine's stock L1 decode
// L0 + L1 . n (s ignored) is >= 0 for every n; the bound is convex, so bilinear filtering and
// mip levels keep it, and it lets the file store L1_c / L0_c in [-1, 1] in 8 bits.

#include <array>
#include <functional>

#include "bake/scene.h"

namespace lb {

// One texel's band: l1[axis] holds the RGB coefficients of world axis x, y or z.
struct ShL1 {
  vec3 l0{0.0f};
  std::array<vec3, 3> l1{vec3(0.0f), vec3(0.0f), vec3(0.0f)};
  float share = 0.0f;  // s: the share of L0 from small sources, in [0, 1]
};

// One estimator sample: light arriving along `direction` (unit, towards its source) whose
// estimate of E/pi at shading normal `normal` is `value` (= L cos / (pi pdf)): its estimate of
// L1, P (value / cos) direction, one RGB vector per axis. 0 when cos <= 0.
std::array<vec3, 3> l1_of_sample(vec3 value, vec3 direction, vec3 normal);

// E/pi at unit shading normal n of a texel whose own (unbumped) normal is n0: the decode above.
vec3 decode_directional(const ShL1& sh, vec3 n, vec3 n0);

// Scales each channel's L1 vector to at most that channel's L0 (both maps in the texel).
void dering(vec3 l0, vec3& l1x, vec3& l1y, vec3& l1z);
inline void dering(ShL1& sh) { dering(sh.l0, sh.l1[0], sh.l1[1], sh.l1[2]); }

// The band of a known radiance field L(w) (W/(sr m^2), w towards the source) over the
// hemisphere about `n0`, by the same estimator the texels use (uniform hemisphere directions,
// side x side stratified, midpoints: deterministic): for tests against closed forms.
ShL1 project_radiance(const std::function<vec3(vec3)>& radiance, vec3 n0, int side);

// A uniform direction on the hemisphere about +z for u in [0, 1)^2 (pdf 1 / (2 pi)).
vec3 square_to_uniform_hemisphere(vec2 u);

}  // namespace lb
