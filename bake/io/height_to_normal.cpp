#include "bake/io/height_to_normal.h"

#include <cmath>

namespace lb {

UvFrame uv_frame(const Scene& scene, int material) {
  glm::dvec2 sum(0.0);
  double area = 0.0, along_v = 0.0;
  for (const Mesh& mesh : scene.meshes) {
    if (mesh.material != material || mesh.uvs.size() != mesh.positions.size()) continue;
    for (const uvec3& t : mesh.triangles) {
      const vec3 e1 = mesh.positions[t.y] - mesh.positions[t.x];
      const vec3 e2 = mesh.positions[t.z] - mesh.positions[t.x];
      const vec2 d1 = mesh.uvs[t.y] - mesh.uvs[t.x], d2 = mesh.uvs[t.z] - mesh.uvs[t.x];
      const float det = d1.x * d2.y - d2.x * d1.y;
      const double a = 0.5 * double(glm::length(glm::cross(e1, e2)));
      if (std::abs(det) < 1e-20f || !(a > 0.0)) continue;
      const vec3 dpdu = (e1 * d2.y - e2 * d1.y) / det;
      const vec3 dpdv = (e2 * d1.x - e1 * d2.x) / det;
      sum += a * glm::dvec2(glm::length(dpdu), glm::length(dpdv));
      area += a;
      if (mesh.tangents.size() == mesh.positions.size()) {
        const vec4 tangent = mesh.tangents[t.x];
        const vec3 n = glm::cross(e1, e2);
        const vec3 b = (tangent.w < 0.0f ? -1.0f : 1.0f) * glm::cross(n, vec3(tangent));
        along_v += glm::dot(b, dpdv) >= 0.0f ? a : -a;
      } else {
        along_v -= a;
      }
    }
  }
  UvFrame frame;
  if (area > 0.0) frame.metres = vec2(sum / area);
  frame.bitangent_along_v = along_v >= 0.0 ? 1.0f : -1.0f;
  return frame;
}

Texture height_to_normal_map(const Texture& height, float bump_scale, const UvFrame& frame) {
  const vec2 metres = frame.metres;
  Texture out;
  out.path = height.path + " (as a normal map)";
  out.width = height.width;
  out.height = height.height;
  out.channels = 3;
  const int w = height.width, h = height.height, c = std::max(1, height.channels);
  out.texels.resize(size_t(w) * size_t(h) * 3);
  const auto at = [&](int i, int j) {  // repeat, as the bump texture is sampled
    i = ((i % w) + w) % w, j = ((j % h) + h) % h;
    return height.texels[(size_t(j) * size_t(w) + size_t(i)) * size_t(c)];
  };
  const float ku = metres.x > 0.0f ? bump_scale / metres.x : 0.0f;
  const float kv = metres.y > 0.0f ? bump_scale / metres.y : 0.0f;
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      // Per unit of u and v; row j + 1 is further along v (row 0 is v = 0).
      const float hu = (at(i + 1, j) - at(i - 1, j)) * 0.5f * float(w);
      const float hv = (at(i, j + 1) - at(i, j - 1)) * 0.5f * float(h);
      const vec3 n = glm::normalize(vec3(-ku * hu, -frame.bitangent_along_v * kv * hv, 1.0f));
      for (int k = 0; k < 3; ++k)
        out.texels[(size_t(j) * size_t(w) + size_t(i)) * 3 + size_t(k)] = 0.5f * n[k] + 0.5f;
    }
  return out;
}

}  // namespace lb
