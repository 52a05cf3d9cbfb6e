#pragma once
// Area lights derived from the scene: every mesh whose material emits is one light.
// Lights are diffuse (Lambertian) emitters on the front side of their triangles.

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
  vec3 power{0.0f};                 // W = pi * radiance * area (Lambertian emitter)
  vec3 centroid{0.0f};              // area-weighted centre
  vec3 normal{0.0f};                // area-weighted mean normal, unit (planar lights: exact)
  std::vector<uint32_t> triangles;  // emitting triangles of `mesh` with non-zero area
  std::vector<float> triangle_cdf;  // cumulative area fraction, last element 1
  std::vector<vec3> triangle_normals;  // unit, per entry of `triangles` (sampling is hot)

  // A point on the light, uniformly distributed over its area, from u in [0,1)^2.
  LightSample sample(const Scene& scene, vec2 u) const;
};

std::vector<AreaLight> collect_lights(const Scene& scene);

// Total emitted power of all lights, W per channel.
vec3 total_power(const std::vector<AreaLight>& lights);

}  // namespace lb
