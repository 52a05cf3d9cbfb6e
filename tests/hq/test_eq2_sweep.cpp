// The light choice's per-light loops in SIMD (bake/transport/eq2_sweep.h) give the scalar
// code's bits: every weight, the four partial sums in their order and the choice's terms, at 4
// and at 8 lanes, for light counts that end inside a vector, a group of four or neither.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <vector>

#include "bake/sampling.h"
#include "bake/transport/eq2_sweep.h"

namespace lb {
namespace {

bool same_bits(float a, float b) {
  return std::memcmp(&a, &b, sizeof(float)) == 0;
}

TEST(Eq2Sweep, SameBitsAsTheScalarLoopAtEveryWidthAndCount) {
  constexpr size_t kMost = 41;
  Rng rng(17);
  std::vector<float> arrays[9];
  for (auto& a : arrays) {
    a.resize(kMost);
    // Centres and normals in [-2, 2]: lights on both sides, some facing away (weight -1).
    for (float& v : a) v = 4.0f * rng.next_float() - 2.0f;
  }
  for (size_t j = 0; j < kMost; ++j) {
    arrays[6][j] = std::abs(arrays[6][j]) * 0.3f;  // radius
    arrays[7][j] = std::abs(arrays[7][j]);         // luminance * area / pi
    arrays[8][j] = std::abs(arrays[8][j]) * 0.1f;  // min d^2
  }
  int negative = 0, positive = 0;
  for (size_t count = 0; count <= kMost; ++count) {
    const Eq2Lights lights{arrays[0].data(), arrays[1].data(), arrays[2].data(),
                           arrays[3].data(), arrays[4].data(), arrays[5].data(),
                           arrays[6].data(), arrays[7].data(), arrays[8].data(), count};
    for (int trial = 0; trial < 20; ++trial) {
      Eq2Receiver x{};
      x.px = rng.next_float() - 0.5f, x.py = rng.next_float() - 0.5f, x.pz = rng.next_float();
      x.gx = 0.0f, x.gy = 1.0f, x.gz = 0.0f;
      x.sx = 0.1f * rng.next_float(), x.sy = 0.99f, x.sz = -0.1f * rng.next_float();
      // The scalar loop DirectLight::eq2_weights ran before the SIMD one.
      std::vector<float> expected(count);
      for (size_t j = 0; j < count; ++j) {
        const float vx = lights.cx[j] - x.px, vy = lights.cy[j] - x.py, vz = lights.cz[j] - x.pz;
        const float d2 = vx * vx + vy * vy + vz * vz;
        const float facing = -(lights.nx[j] * vx + lights.ny[j] * vy + lights.nz[j] * vz);
        const float above = x.gx * vx + x.gy * vy + x.gz * vz + lights.radius[j];
        const float cos_x_d = std::max(x.sx * vx + x.sy * vy + x.sz * vz, 0.0f);
        const float w =
            lights.lum_area[j] * cos_x_d * facing / (d2 * std::max(d2, lights.min_d2[j]));
        expected[j] = std::min(above, facing) > 0.0f ? w : -1.0f;
        (expected[j] < 0.0f ? negative : positive) += 1;
      }
      // Sum k takes lights k, k + 4, ... of the whole groups of four; sum 0 then the rest.
      const size_t grouped = count / 4 * 4;
      float partial_expected[4] = {0.0f, 0.0f, 0.0f, 0.0f};
      for (size_t k = 0; k < 4; ++k)
        for (size_t i = k; i < grouped; i += 4) partial_expected[k] += std::max(expected[i], 0.0f);
      for (size_t i = grouped; i < count; ++i) partial_expected[0] += std::max(expected[i], 0.0f);
      const int reachable_expected = int(std::count_if(
          expected.begin(), expected.end(), [](float w) { return w >= 0.0f; }));
      const double scale = 0.37, uniform = 0.01;
      for (const bool widest : {false, true}) {
        std::vector<float> out(count + 1, 7.0f);
        float partial[4];
        int reachable = -1;
        eq2_sweep(lights, x, out.data(), partial, reachable, widest);
        for (size_t i = 0; i < count; ++i)
          ASSERT_TRUE(same_bits(out[i], expected[i]))
              << "count " << count << " light " << i << " widest " << widest;
        EXPECT_EQ(out[count], 7.0f) << "wrote past the lights";
        for (int k = 0; k < 4; ++k)
          ASSERT_TRUE(same_bits(partial[k], partial_expected[k])) << "count " << count;
        EXPECT_EQ(reachable, reachable_expected);
        std::vector<double> terms(count);
        choice_terms(expected.data(), count, scale, uniform, terms.data(), widest);
        for (size_t i = 0; i < count; ++i)
          ASSERT_EQ(terms[i], double(std::max(expected[i], 0.0f)) * scale + uniform);
      }
    }
  }
  // Both branches of the reach test were taken.
  EXPECT_GT(negative, 1000);
  EXPECT_GT(positive, 1000);
}

}  // namespace
}  // namespace lb
