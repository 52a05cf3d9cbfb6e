#include "bake/hq/bump.h"

#include <cmath>

namespace lb {

namespace {

struct UvFrame {
  vec3 dp_du{0.0f};
  vec3 dp_dv{0.0f};
  bool valid = false;
};

// Derivatives of position with respect to the texture coordinates over one triangle.
UvFrame uv_frame(const Mesh& mesh, uint32_t triangle) {
  UvFrame frame;
  if (mesh.uvs.empty()) return frame;
  const uvec3 tri = mesh.triangles[triangle];
  const vec3 e1 = mesh.positions[tri.y] - mesh.positions[tri.x];
  const vec3 e2 = mesh.positions[tri.z] - mesh.positions[tri.x];
  const vec2 d1 = mesh.uvs[tri.y] - mesh.uvs[tri.x];
  const vec2 d2 = mesh.uvs[tri.z] - mesh.uvs[tri.x];
  const float det = d1.x * d2.y - d1.y * d2.x;
  if (std::abs(det) < 1e-20f) return frame;
  frame.dp_du = (e1 * d2.y - e2 * d1.y) / det;
  frame.dp_dv = (e2 * d1.x - e1 * d2.x) / det;
  frame.valid = true;
  return frame;
}

vec3 same_side(vec3 n, vec3 reference) {
  const float length = glm::length(n);
  if (!(length > 0.0f) || !std::isfinite(length)) return reference;
  n /= length;
  return glm::dot(n, reference) < 0.0f ? -n : n;
}

vec3 height_bump(const Scene& scene, const SurfacePoint& sp, const Texture& texture, float scale) {
  const Mesh& mesh = scene.meshes[sp.mesh];
  const UvFrame frame = uv_frame(mesh, sp.triangle);
  if (!frame.valid) return sp.shading_normal;
  const vec3 n = sp.shading_normal;
  const float du = 1.0f / float(std::max(texture.width, 1));
  const float dv = 1.0f / float(std::max(texture.height, 1));
  auto height = [&](vec2 uv) { return sample_texture(texture, uv).x * scale; };
  const float dh_du = (height(sp.uv + vec2(du, 0)) - height(sp.uv - vec2(du, 0))) / (2.0f * du);
  const float dh_dv = (height(sp.uv + vec2(0, dv)) - height(sp.uv - vec2(0, dv))) / (2.0f * dv);
  const vec3 dp_du = frame.dp_du + dh_du * n;
  const vec3 dp_dv = frame.dp_dv + dh_dv * n;
  return same_side(glm::cross(dp_du, dp_dv), n);
}

vec3 normal_map_bump(const Scene& scene, const SurfacePoint& sp, const Texture& texture,
                     float scale) {
  const vec3 n = sp.shading_normal;
  vec3 tangent = vec3(sp.tangent);
  float handedness = sp.tangent.w < 0.0f ? -1.0f : 1.0f;
  if (glm::dot(tangent, tangent) < 1e-12f) {
    const UvFrame frame = uv_frame(scene.meshes[sp.mesh], sp.triangle);
    if (!frame.valid) return n;
    tangent = frame.dp_du;
    handedness = glm::dot(glm::cross(n, frame.dp_du), frame.dp_dv) < 0.0f ? -1.0f : 1.0f;
  }
  tangent -= n * glm::dot(n, tangent);
  if (glm::dot(tangent, tangent) < 1e-12f) return n;
  tangent = glm::normalize(tangent);
  const vec3 bitangent = handedness * glm::cross(n, tangent);
  const vec3 c = vec3(sample_texture(texture, sp.uv));
  vec3 local = 2.0f * c - 1.0f;
  local.x *= scale;
  local.y *= scale;
  return same_side(tangent * local.x + bitangent * local.y + n * local.z, n);
}

}  // namespace

vec3 bumped_normal(const Scene& scene, const SurfacePoint& sp) {
  const Material& material = *sp.material;
  if (material.bump == BumpKind::none || material.bump_texture < 0 ||
      size_t(material.bump_texture) >= scene.textures.size())
    return sp.shading_normal;
  const Texture& texture = scene.textures[size_t(material.bump_texture)];
  if (material.bump == BumpKind::height)
    return height_bump(scene, sp, texture, material.bump_scale);
  return normal_map_bump(scene, sp, texture, material.bump_scale);
}

}  // namespace lb
