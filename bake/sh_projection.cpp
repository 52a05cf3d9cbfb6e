#include "bake/sh_projection.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/constants.hpp>

#include "bake/sampling.h"

namespace lb {

std::array<vec3, 3> l1_of_sample(vec3 value, vec3 direction, vec3 normal) {
  const float cosine = glm::dot(direction, normal);
  if (!(cosine > 0.0f)) return {vec3(0.0f), vec3(0.0f), vec3(0.0f)};
  const vec3 tangential = (direction - normal * cosine) / cosine;
  return {value * tangential.x, value * tangential.y, value * tangential.z};
}

vec3 decode_directional(const ShL1& sh, vec3 n, vec3 n0) {
  const float weight = 0.5f * (1.0f + sh.share);  // W = (1 + s) / 2
  const float flat = 1.0f - weight * (1.0f - glm::dot(n, n0));
  return glm::max(sh.l0 * flat + sh.l1[0] * n.x + sh.l1[1] * n.y + sh.l1[2] * n.z, vec3(0.0f));
}

void dering(vec3 l0, vec3& l1x, vec3& l1y, vec3& l1z) {
  for (int c = 0; c < 3; ++c) {
    const float length = std::sqrt(l1x[c] * l1x[c] + l1y[c] * l1y[c] + l1z[c] * l1z[c]);
    const float bound = std::max(l0[c], 0.0f);
    if (length > bound) {
      const float scale = bound / length;
      l1x[c] *= scale, l1y[c] *= scale, l1z[c] *= scale;
    }
  }
}

vec3 square_to_uniform_hemisphere(vec2 u) {
  const float z = u.x;
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  const float phi = 2.0f * glm::pi<float>() * u.y;
  return {r * std::cos(phi), r * std::sin(phi), z};
}

ShL1 project_radiance(const std::function<vec3(vec3)>& radiance, vec3 n0, int side) {
  const Frame frame(n0);
  glm::dvec3 l0(0.0), l1[3] = {glm::dvec3(0.0), glm::dvec3(0.0), glm::dvec3(0.0)};
  const int n = std::max(1, side);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const vec2 u((float(i) + 0.5f) / float(n), (float(j) + 0.5f) / float(n));
      const vec3 w = frame.to_world(square_to_uniform_hemisphere(u));
      // pdf 1/(2 pi): E/pi = (1/pi) L cos / pdf = 2 L cos.
      const vec3 value = 2.0f * radiance(w) * glm::dot(w, n0);
      const std::array<vec3, 3> band = l1_of_sample(value, w, n0);
      l0 += glm::dvec3(value);
      for (int a = 0; a < 3; ++a) l1[a] += glm::dvec3(band[size_t(a)]);
    }
  const double count = double(n) * double(n);
  ShL1 out;
  out.l0 = vec3(l0 / count);
  for (int a = 0; a < 3; ++a) out.l1[size_t(a)] = vec3(l1[a] / count);
  return out;
}

}  // namespace lb
