#pragma once
// Reading an exported lightmap back the way an engine does (bilinear at TEXCOORD_1), at points
// spread over a mesh, for tests against closed forms.

#include <algorithm>
#include <cmath>
#include <vector>

#include "bake/bake_result.h"
#include "bake/lightmap/lightmap.h"
#include "bake/pipeline/bake.h"
#include "bake/sampling.h"
#include "test_helpers.h"

namespace lb {

// Points spread over mesh m in proportion to area (seeded), with their map value.
struct MapReadPoint {
  vec3 position;
  vec3 value;
};
inline std::vector<MapReadPoint> read_back(const Scene& scene, const BakeResult& bake,
                                          const Lightmap& map, size_t m, float per_m2) {
  const Mesh mesh = mesh_with_lightmap(scene.meshes[m], bake.illumination, m);
  std::vector<MapReadPoint> points;
  Rng rng(7);
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const uvec3 tri = mesh.triangles[t];
    const int n = std::max(1, int(std::lround(triangle_area(mesh, t) * per_m2)));
    for (int k = 0; k < n; ++k) {
      const vec2 u = rng.next_2d();
      const float s = std::sqrt(u.x), b0 = 1 - s, b1 = s * (1 - u.y), b2 = s * u.y;
      const vec3 p =
          b0 * mesh.positions[tri.x] + b1 * mesh.positions[tri.y] + b2 * mesh.positions[tri.z];
      const vec2 uv = b0 * mesh.lightmap_uvs[tri.x] + b1 * mesh.lightmap_uvs[tri.y] +
                      b2 * mesh.lightmap_uvs[tri.z];
      points.push_back({p, bilinear_read(map.radiance, map.width, map.height, uv)});
    }
  }
  return points;
}

// A 4 x 4 m black floor at y = 0 facing up (mesh 0, material 0: black; nothing bounces).
inline Scene black_floor() {
  Scene scene;
  Material black;
  black.reflectance = vec3(0.0f);
  const int b = test::add_material(scene, black);
  scene.meshes.push_back(test::make_quad({-2, 0, 2}, {4, 0, 0}, {0, 0, -4}, b, "floor"));
  return scene;
}

// A bake at a game density with light radiosity settings (the tests' light is direct).
inline BakeParams bake_at(float texels_per_m) {
  BakeParams params;
  params.illumination.texel_size = 1.0f / texels_per_m;
  params.radiosity.ray_budget = 200'000;
  params.soft_texels.gather_rays = 2;
  params.soft_texels.game_gather_budget = 0.0;  // cheap: these tests measure where light goes
  return params;
}

}  // namespace lb
