#pragma once
// Area lights derived from the scene: every mesh whose material emits is one light.
// Lights are diffuse (Lambertian) emitters on the front side of their triangles, and on the
// back too when the material says so (Material::two_sided_emission).

#include <algorithm>
#include <cmath>
#include <vector>

#include "bake/scene.h"

namespace lb {

struct LightSample {
  vec3 position;
  vec3 normal;  // front side, unit
  float pdf_area = 0.0f;  // 1 / light area for uniform area sampling, 1/m^2
};

struct AreaLight {
  int mesh = -1;
  vec3 radiance{0.0f};              // W/(sr m^2)
  float area = 0.0f;                // m^2
  bool two_sided = false;           // emits `radiance` from the back as well (normal reversed)
  vec3 power{0.0f};                 // W = pi * radiance * area (Lambertian), x2 if two-sided
  vec3 centroid{0.0f};              // area-weighted centre
  vec3 normal{0.0f};                // area-weighted mean normal, unit (planar lights: exact)
  std::vector<uint32_t> triangles;  // emitting triangles of `mesh` with non-zero area
  std::vector<float> triangle_cdf;  // cumulative area fraction, last element 1
  std::vector<vec3> triangle_normals;  // unit, per entry of `triangles` (sampling is hot)

  // A point on the light, uniformly distributed over its area, from u in [0,1)^2.
  LightSample sample(const Scene& scene, vec2 u) const;
  // The cosine at the light of light leaving it towards unit `direction` from a point whose
  // front normal is `normal`: |cos| for a two-sided light, else the signed cosine.
  float emitting_cosine(vec3 normal, vec3 direction) const {
    const float c = glm::dot(normal, direction);
    return two_sided ? std::abs(c) : c;
  }
  float pick_side(float& u_x) const;  // pick_emitting_side for this light
};

// Which side of an emitter a ray leaves from, as u_x in [0,1) decides: the front for a
// one-sided emitter (u_x unchanged, so its rays keep their bits); for a two-sided one each
// side half the time, u_x stretched back onto [0,1) so it stays stratified. Returns the
// side's normal sign.
inline float pick_emitting_side(bool two_sided, float& u_x) {
  if (!two_sided) return 1.0f;
  const bool back = u_x >= 0.5f;
  u_x = std::min(2.0f * u_x - (back ? 1.0f : 0.0f), 0.99999994f);
  return back ? -1.0f : 1.0f;
}

inline float AreaLight::pick_side(float& u_x) const {
  return pick_emitting_side(two_sided, u_x);
}

// The triangle u_x picks by area among `count` (the first CDF entry >= u_x) and u_x rescaled
// into [0,1] inside it, so a light's sample stays stratified. Returned apart from the caller's
// vec2: writing one float of a vec2 that is then read whole stalls on store forwarding.
struct PickedTriangle {
  size_t index;
  float u_x;
};
inline PickedTriangle pick_triangle(const float* cdf, size_t count, float u_x) {
  const size_t index = std::min(size_t(std::lower_bound(cdf, cdf + count, u_x) - cdf), count - 1);
  const float lo = index == 0 ? 0.0f : cdf[index - 1];
  const float hi = cdf[index];
  return {index, hi > lo ? std::clamp((u_x - lo) / (hi - lo), 0.0f, 1.0f) : 0.5f};
}

// The point of barycentrics b = (b1, b2) on the triangle p0 p1 p2.
inline vec3 point_on_triangle(vec3 p0, vec3 p1, vec3 p2, vec2 b) {
  return (1.0f - b.x - b.y) * p0 + b.x * p1 + b.y * p2;
}

std::vector<AreaLight> collect_lights(const Scene& scene);

// Total emitted power of all lights, W per channel.
vec3 total_power(const std::vector<AreaLight>& lights);

}  // namespace lb
