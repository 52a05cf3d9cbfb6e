#pragma once
// What a ray hit: position, normals, texture coordinates and material at the hit point.

#include "bake/accel.h"
#include "bake/scene.h"

namespace lb {

struct SurfacePoint {
  vec3 position{0.0f};
  vec3 geometric_normal{0.0f};  // unit, front side of the triangle
  vec3 shading_normal{0.0f};    // interpolated vertex normal (or geometric), unit
  vec2 uv{0.0f};
  vec2 lightmap_uv{0.0f};
  vec4 tangent{0.0f};
  uint32_t mesh = 0;
  uint32_t triangle = 0;
  vec2 barycentric{0.0f};
  const Material* material = nullptr;
};

SurfacePoint surface_at(const Scene& scene, const Hit& hit, const Ray& ray);

// Reflectance at a surface point: the material's colour times its texture, if any.
vec3 reflectance_at(const Scene& scene, const SurfacePoint& sp);

// The texture at `uv` as its sampler reads it (bilinear or nearest; repeated, clamped to the
// edge or mirrored per axis, as OpenGL's samplers); returns channels 0..3 (missing ones = 1).
vec4 sample_texture(const Texture& texture, vec2 uv);

}  // namespace lb
