#pragma once
// Per-ray stratum jitter for radiosity shots: 16 random bits per axis from one 32-bit draw of
// a counter-based generator (mix64 in sampling.h), instead of two calls to a stateful one.
// tests/radiosity/test_shot_sampling.cpp holds it to its stratum.

#include <cstdint>

#include "bake/scene.h"

namespace lb::shot {

// A jittered point in stratum (i, j) of a grid of `inverse_side` = 1 / side, from 32 random
// bits: 16 bits of jitter per axis are plenty inside a stratum. Kept below 1: in a wide grid
// the last stratum's sum rounds up to side.
inline vec2 jittered_stratum(uint32_t i, uint32_t j, float inverse_side, uint32_t bits) {
  constexpr float unit = 1.0f / 65536.0f;
  const vec2 jitter(float(bits & 0xffffu) * unit, float(bits >> 16) * unit);
  return glm::min((vec2(float(i), float(j)) + jitter) * inverse_side, vec2(0.99999994f));
}

}  // namespace lb::shot
