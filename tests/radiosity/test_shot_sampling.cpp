// The radiosity shots' stratum jitter (bake/radiosity/shot_sampling.h) and the counter-based
// generator it draws from.

#include <gtest/gtest.h>

#include <cmath>

#include "bake/radiosity/shot_sampling.h"
#include "bake/sampling.h"

namespace lb {
namespace {

TEST(ShotSampling, JitterStaysInItsStratum) {
  for (uint32_t side : {1u, 3u, 64u, 1000u, 65535u}) {
    const float inverse = 1.0f / float(side);
    for (uint32_t i : {0u, side / 2, side - 1})
      for (uint32_t bits : {0u, 0xffffffffu, 0x8000ffffu, 0x12345678u}) {
        const vec2 u = shot::jittered_stratum(i, side - 1 - i, inverse, bits);
        // The stratum [i, i + 1) / side, to float rounding of the product.
        EXPECT_GE(u.x, float(i) * inverse * (1.0f - 1e-6f));
        EXPECT_LT(u.x, float(i + 1) * inverse * (1.0f + 1e-6f));
        EXPECT_GE(u.y, float(side - 1 - i) * inverse * (1.0f - 1e-6f));
        EXPECT_LT(u.y, float(side - i) * inverse * (1.0f + 1e-6f));
        EXPECT_LT(u.x, 1.0f);
        EXPECT_LT(u.y, 1.0f);
      }
  }
}

TEST(ShotSampling, CounterGeneratorIsUniform) {
  // Chi-square of the top 4 bits of each 32-bit half over 16 bins, 160 000 draws: 15 degrees
  // of freedom, so a sound generator stays under 37.7 (p = 0.001).
  for (int half = 0; half < 2; ++half) {
    int bins[16] = {};
    const uint64_t key = hash_seed(1, 2, 3);
    for (uint64_t k = 0; k < 160'000; ++k)
      ++bins[(mix64(key + k * 0x9e3779b97f4a7c15ULL) >> (half ? 60 : 28)) & 15];
    double chi2 = 0.0;
    for (int count : bins) chi2 += (count - 10'000.0) * (count - 10'000.0) / 10'000.0;
    EXPECT_LT(chi2, 37.7) << "half " << half;
  }
}

}  // namespace
}  // namespace lb
