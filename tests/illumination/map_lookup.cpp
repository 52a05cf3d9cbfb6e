#include "map_lookup.h"

#include <gtest/gtest.h>

#include <cmath>

namespace lb::test {

// Bilinear read of the map at an atlas UV, as the GPU does it.
vec3 map_at_uv(const IlluminationMaps& maps, vec2 uv) {
  const vec2 s = uv * vec2(float(maps.width), float(maps.height)) - 0.5f;
  const int i = int(std::floor(s.x)), j = int(std::floor(s.y));
  const vec2 f = s - glm::floor(s);
  auto at = [&](int x, int y) { return maps.radiance[size_t(y) * size_t(maps.width) + size_t(x)]; };
  return (1 - f.x) * (1 - f.y) * at(i, j) + f.x * (1 - f.y) * at(i + 1, j) +
         (1 - f.x) * f.y * at(i, j + 1) + f.x * f.y * at(i + 1, j + 1);
}

vec3 map_at(const IlluminationMaps& maps, const Scene& scene, size_t mesh, vec3 p) {
  // Find the triangle containing p (planar quad meshes) and interpolate the lightmap UVs.
  const Mesh& m = scene.meshes[mesh];
  for (size_t t = 0; t < m.triangles.size(); ++t) {
    const uvec3 tri = m.triangles[t];
    const vec3 a = m.positions[tri.x], e1 = m.positions[tri.y] - a, e2 = m.positions[tri.z] - a,
               d = p - a;
    const float d11 = glm::dot(e1, e1), d12 = glm::dot(e1, e2), d22 = glm::dot(e2, e2);
    const float det = d11 * d22 - d12 * d12;
    const float b1 = (d22 * glm::dot(d, e1) - d12 * glm::dot(d, e2)) / det;
    const float b2 = (d11 * glm::dot(d, e2) - d12 * glm::dot(d, e1)) / det;
    if (b1 < -1e-5f || b2 < -1e-5f || b1 + b2 > 1 + 1e-5f) continue;
    const auto& uv = maps.lightmap_uvs[mesh];
    return map_at_uv(maps, (1 - b1 - b2) * uv[tri.x] + b1 * uv[tri.y] + b2 * uv[tri.z]);
  }
  ADD_FAILURE() << "point not on mesh " << mesh;
  return vec3(0.0f);
}

}  // namespace lb::test
