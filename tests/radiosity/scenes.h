#pragma once
// Scenes built in code for the radiosity tests and benchmark.

#include <array>
#include <functional>
#include <map>

#include "bake/bake_result.h"
#include "bake/scene.h"

namespace lb::test {

// The default room: a 4 x 3 x 4 m closed box (inward, albedo 0.75), a 1 x 1.2 x 1 m block on
// the floor (albedo 0.6/0.5/0.4) and a 1 x 1 m light quad just under the ceiling facing down
// (radiance 10 W/(sr m^2), albedo 0.8).
Scene make_room();

// make_room() with a mirror on one wall and a smooth ball in its light, so pass 1 has caustics
// to store too (and the atlas must split the ball's vertices).
Scene make_room_with_mirror();

// An open scene (y up): a 4 x 4 m floor (albedo 0.7/0.5/0.3), a wall of the same, a mirror
// wall (R 0.9), a glass box and a glossy metal plate; with `light`, a 0.8 m square light
// (radiance 5/4/3, albedo 0.5) 1.8 m up facing down, its last mesh.
Scene make_open_scene(bool light);

// Sets an equirect sky on `scene`: radiance (0.5, 0.6, 0.8) times an 8 x 4 RGB image whose
// texels differ in brightness (up to 40x: a sun-like texel) and colour.
void add_sky_image(Scene& scene);

// Integral of the vertex radiance (linearly interpolated) over a radiosity mesh, W/sr per
// channel; times pi it is the incident power the mesh received.
glm::dvec3 integrate(const MeshRadiosity& r);

// Edge uses with vertices welded by position (to 1e-6 m: make_sphere's pole vertices differ
// by ~1e-8): 2 everywhere means a closed, crack-free (no T-junction) surface.
std::map<std::pair<std::array<float, 3>, std::array<float, 3>>, int> edge_uses(const Mesh& mesh);

// A copy of `mesh` with only the triangles `keep` accepts, vertices compacted.
Mesh extract_triangles(const Mesh& mesh, const std::function<bool(size_t)>& keep);

// A closed sphere (radius 1, inward) of albedo rho whose top cap (theta < cap_degrees) emits
// radiance `emission`; two meshes sharing the cap's rim exactly.
Scene make_emitting_sphere(float rho, float emission, float cap_degrees, int rings, int segments);

}  // namespace lb::test
