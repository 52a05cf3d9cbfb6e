#include "bake/sampling.h"

#include <cmath>

#include <glm/gtc/constants.hpp>

namespace lb {

Rng::Rng(uint64_t seed, uint64_t stream) : inc_((stream << 1u) | 1u) {
  next_u32();
  state_ += seed;
  next_u32();
}

uint32_t Rng::next_u32() {
  const uint64_t old = state_;
  state_ = old * 6364136223846793005ULL + inc_;
  const uint32_t xorshifted = uint32_t(((old >> 18u) ^ old) >> 27u);
  const uint32_t rot = uint32_t(old >> 59u);
  return (xorshifted >> rot) | (xorshifted << ((~rot + 1u) & 31u));
}

float Rng::next_float() {
  // 24 random mantissa bits: exactly representable, strictly below 1.
  return float(next_u32() >> 8) * 0x1p-24f;
}

uint64_t hash_seed(uint64_t a, uint64_t b, uint64_t c) {
  auto mix = [](uint64_t z) {
    z += 0x9e3779b97f4a7c15ULL;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  };
  return mix(a ^ mix(b ^ mix(c)));
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

glm::vec3 square_to_cosine_hemisphere(glm::vec2 u) {
  const glm::vec2 d = square_to_disk(u);
  const float z = std::sqrt(std::max(0.0f, 1.0f - d.x * d.x - d.y * d.y));
  return {d.x, d.y, z};
}

glm::vec2 square_to_triangle(glm::vec2 u) {
  // Heitz 2019: area-preserving and low-distortion, keeps strata compact.
  float b0, b1;
  if (u.y > u.x) {
    b0 = u.x / 2.0f;
    b1 = u.y - b0;
  } else {
    b1 = u.y / 2.0f;
    b0 = u.x - b1;
  }
  return {b1, 1.0f - b0 - b1};
}

Frame::Frame(glm::vec3 n) : normal(n) {
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float b = n.x * n.y * a;
  tangent = {1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x};
  bitangent = {b, sign + n.y * n.y * a, -n.y};
}

}  // namespace lb
