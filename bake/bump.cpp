#include "bake/bump.h"

#include <cmath>

namespace lb {

namespace {

vec3 same_side(vec3 n, vec3 reference) {
  const float length = glm::length(n);
  if (!(length > 0.0f) || !std::isfinite(length)) return reference;
  n /= length;
  return glm::dot(n, reference) < 0.0f ? -n : n;
}

vec3 height_bump(const Scene& scene, const SurfacePoint& sp, const Texture& texture, float scale) {
  const Mesh& mesh = scene.meshes[sp.mesh];
  const std::optional<UvDerivatives> frame = uv_derivatives(mesh, sp.triangle);
  if (!frame) return sp.shading_normal;
  const vec3 n = sp.shading_normal;
  const float du = 1.0f / float(std::max(texture.width, 1));
  const float dv = 1.0f / float(std::max(texture.height, 1));
  auto height = [&](vec2 uv) { return sample_texture(texture, uv).x * scale; };
  const float dh_du = (height(sp.uv + vec2(du, 0)) - height(sp.uv - vec2(du, 0))) / (2.0f * du);
  const float dh_dv = (height(sp.uv + vec2(0, dv)) - height(sp.uv - vec2(0, dv))) / (2.0f * dv);
  const vec3 dp_du = frame->dp_du + dh_du * n;
  const vec3 dp_dv = frame->dp_dv + dh_dv * n;
  return same_side(glm::cross(dp_du, dp_dv), n);
}

vec3 normal_map_bump(const Scene& scene, const SurfacePoint& sp, const Texture& texture,
                     float scale) {
  const vec3 n = sp.shading_normal;
  vec3 tangent = vec3(sp.tangent);
  float handedness = sp.tangent.w < 0.0f ? -1.0f : 1.0f;
  if (glm::dot(tangent, tangent) < 1e-12f) {
    const std::optional<UvDerivatives> frame = uv_derivatives(scene.meshes[sp.mesh], sp.triangle);
    if (!frame) return n;
    tangent = frame->dp_du;
    handedness = glm::dot(glm::cross(n, frame->dp_du), frame->dp_dv) < 0.0f ? -1.0f : 1.0f;
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

vec3 specular_normal(const Scene& scene, const SurfacePoint& sp, vec3 incident) {
  const vec3 shading = bumped_normal(scene, sp);
  const bool agree =
      (glm::dot(incident, shading) < 0.0f) == (glm::dot(incident, sp.geometric_normal) < 0.0f);
  return agree ? shading : sp.geometric_normal;
}

}  // namespace lb
