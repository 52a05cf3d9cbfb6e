#include "bake/sampling.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/constants.hpp>

namespace lb {

Rng::Rng(uint64_t seed, uint64_t stream) : inc_((stream << 1u) | 1u) {
  next_u32();
  state_ += seed;
  next_u32();
}

glm::vec2 square_to_disk(glm::vec2 u) {
  const glm::vec2 offset = 2.0f * u - 1.0f;
  if (offset.x == 0.0f && offset.y == 0.0f) return {0.0f, 0.0f};
  const float quarter_pi = glm::quarter_pi<float>();
  float r, theta;
  if (std::abs(offset.x) > std::abs(offset.y)) {
    r = offset.x;
    theta = quarter_pi * (offset.y / offset.x);
  } else {
    r = offset.y;
    theta = glm::half_pi<float>() - quarter_pi * (offset.x / offset.y);
  }
  return r * glm::vec2(std::cos(theta), std::sin(theta));
}

Frame::Frame(glm::vec3 n) : normal(n) {
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float b = n.x * n.y * a;
  tangent = {1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x};
  bitangent = {b, sign + n.y * n.y * a, -n.y};
}

bool survive_roulette(glm::vec3& throughput, float threshold, float u) {
  const float strength = std::max({throughput.x, throughput.y, throughput.z});
  if (!(strength > 0.0f)) return false;
  if (strength >= threshold) return true;
  const float survive = strength / threshold;
  if (u >= survive) return false;
  throughput /= survive;
  return true;
}

bool survive_roulette(glm::vec3& throughput, float threshold, Rng& rng) {
  const float strength = std::max({throughput.x, throughput.y, throughput.z});
  if (!(strength > 0.0f)) return false;
  return strength >= threshold || survive_roulette(throughput, threshold, rng.next_float());
}

}  // namespace lb
