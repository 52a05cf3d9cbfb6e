// The sequence behind HQ's progressive strata (bake/sobol_points.h): the stratification its
// comment promises, with and without a shift, and a uniform point over the shift.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "bake/sampling.h"
#include "bake/sobol_points.h"

namespace lb {
namespace {

// True when the 2^m points from `first` put exactly one point in every box of width 2^-a and
// height 2^-(m-a), for every a in [0, m]: a (0,m,2)-net in base 2.
bool is_net(uint32_t first, int m, uint64_t shift, int dimension) {
  const uint32_t count = 1u << m;
  for (int a = 0; a <= m; ++a) {
    std::vector<int> boxes(count, 0);
    for (uint32_t i = first; i < first + count; ++i) {
      const uint32_t x = sobol_coordinate(i, dimension) ^ uint32_t(shift);
      const uint32_t y = sobol_coordinate(i, dimension + 1) ^ uint32_t(shift >> 32);
      const uint32_t column = a == 0 ? 0 : x >> (32 - a);
      const uint32_t row = m - a == 0 ? 0 : y >> (32 - (m - a));
      if (++boxes[(row << a) | column] > 1) return false;
    }
  }
  return true;
}

TEST(SobolPoints, FirstPointsOfEachDimension) {
  // Direction numbers as binary fractions: dimension 0 halves (van der Corput), dimension 1
  // 1/2, 3/4, 5/8, 15/16, dimension 2 1/2, 3/4, 3/8, dimension 3 1/2, 3/4, 1/8.
  const double expected[4][4] = {{0.5, 0.25, 0.125, 0.0625},
                                 {0.5, 0.75, 0.625, 0.9375},
                                 {0.5, 0.75, 0.375, 0.5625},
                                 {0.5, 0.75, 0.125, 0.3125}};
  for (int d = 0; d < 4; ++d)
    for (int k = 0; k < 4; ++k)
      EXPECT_EQ(sobol_coordinate(1u << k, d) * 0x1p-32, expected[d][k]) << d << " " << k;
  for (int d = 0; d < 4; ++d) EXPECT_EQ(sobol_coordinate(0, d), 0u);
}

TEST(SobolPoints, DimensionsZeroAndOneAreAZeroTwoSequence) {
  // Every aligned block of 2^m points is a (0,m,2)-net: HQ's pass k (16 points from 16 k) a
  // 4 x 4 grid, passes 0..15 a 16 x 16 one; a digital shift keeps it.
  for (uint64_t shift : {uint64_t(0), uint64_t(0x9e3779b97f4a7c15ull), ~uint64_t(0)})
    for (int m = 0; m <= 10; ++m)
      for (uint32_t block = 0; block < 4; ++block)
        EXPECT_TRUE(is_net(block << m, m, shift, 0)) << m << " " << block << " " << shift;
  // A block that does not start at a multiple of its size is not promised (and is not one).
  EXPECT_FALSE(is_net(3, 4, 0, 0));
}

TEST(SobolPoints, EveryDimensionStratifiesOnItsOwn) {
  // Each coordinate alone is a (0,1)-sequence: 2^m aligned points, one in each 2^-m interval.
  for (int d = 0; d < 4; ++d)
    for (int m = 1; m <= 12; m += 3) {
      std::vector<int> cells(1u << m, 0);
      for (uint32_t i = 5u << m; i < (6u << m); ++i)
        ++cells[(sobol_coordinate(i, d) ^ 0xdeadbeefu) >> (32 - m)];
      for (int c : cells) ASSERT_EQ(c, 1) << d << " " << m;
    }
}

TEST(SobolPoints, AShiftedPointIsUniformOverTheShift) {
  // The estimates built on these points are unbiased because each point is uniform over a
  // random shift: 64 x 64 bins of point 37 over 2^20 shifts, chi-square within 5 sigma of its
  // 4095 degrees of freedom (measured 4138; the bound is 4095 +- 453).
  constexpr int kBins = 64;
  constexpr int kDraws = 1 << 20;
  std::vector<int> bins(kBins * kBins, 0);
  for (int k = 0; k < kDraws; ++k) {
    const glm::vec2 p = shifted_sobol_point(37, mix64(uint64_t(k)), 2);
    ASSERT_GE(p.x, 0.0f);
    ASSERT_LT(p.x, 1.0f);
    ASSERT_LT(p.y, 1.0f);
    ++bins[int(p.y * kBins) * kBins + int(p.x * kBins)];
  }
  const double expected = double(kDraws) / (kBins * kBins);
  double chi2 = 0.0;
  for (int b : bins) chi2 += (b - expected) * (b - expected) / expected;
  const double dof = kBins * kBins - 1;
  EXPECT_NEAR(chi2, dof, 5.0 * std::sqrt(2.0 * dof));
}

}  // namespace
}  // namespace lb
