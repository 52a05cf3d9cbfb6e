#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>
#include <glm/gtc/constants.hpp>

#include "bake/sampling.h"

namespace lb {
namespace {

TEST(Rng, SameSeedSameStreamGivesSameNumbers) {
  Rng a(42, 7), b(42, 7), c(42, 8);
  bool differs = false;
  for (int i = 0; i < 100; ++i) {
    const uint32_t x = a.next_u32();
    EXPECT_EQ(x, b.next_u32());
    differs |= x != c.next_u32();
  }
  EXPECT_TRUE(differs);
}

TEST(Rng, FloatsAreInUnitIntervalWithMeanOneHalf) {
  Rng rng(1);
  double sum = 0.0;
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    const float x = rng.next_float();
    ASSERT_GE(x, 0.0f);
    ASSERT_LT(x, 1.0f);
    sum += x;
  }
  EXPECT_NEAR(sum / n, 0.5, 3e-3);  // 5 sigma of 1/sqrt(12 n)
}

TEST(SquareToDisk, CornersAndCentreLandOnKnownPoints) {
  EXPECT_NEAR(glm::length(square_to_disk({0.5f, 0.5f})), 0.0f, 1e-7f);
  for (glm::vec2 corner : {glm::vec2(0, 0), glm::vec2(1, 0), glm::vec2(0, 1), glm::vec2(1, 1)})
    EXPECT_NEAR(glm::length(square_to_disk(corner)), 1.0f, 1e-6f);
}

TEST(SquareToDisk, IsAreaPreserving) {
  // Uniform on the square -> uniform on the disk: the fraction inside radius r is r^2.
  Rng rng(3);
  const int n = 200000;
  int inside_half = 0;
  for (int i = 0; i < n; ++i) inside_half += glm::length(square_to_disk(rng.next_2d())) < 0.5f;
  EXPECT_NEAR(double(inside_half) / n, 0.25, 0.005);
}

TEST(SquareToCosineHemisphere, HasCosineDistribution) {
  // For pdf cos/pi: E[cos theta] = 2/3 and E[cos^2 theta] = 1/2.
  Rng rng(5);
  const int n = 200000;
  double sum_cos = 0.0, sum_cos2 = 0.0;
  for (int i = 0; i < n; ++i) {
    const glm::vec3 d = square_to_cosine_hemisphere(rng.next_2d());
    ASSERT_NEAR(glm::length(d), 1.0f, 1e-5f);
    ASSERT_GE(d.z, 0.0f);
    sum_cos += d.z;
    sum_cos2 += d.z * d.z;
  }
  EXPECT_NEAR(sum_cos / n, 2.0 / 3.0, 3e-3);
  EXPECT_NEAR(sum_cos2 / n, 0.5, 3e-3);
}

TEST(SquareToTriangle, StaysInsideAndIsUniform) {
  Rng rng(9);
  const int n = 100000;
  glm::dvec2 mean(0.0);
  for (int i = 0; i < n; ++i) {
    const glm::vec2 b = square_to_triangle(rng.next_2d());
    ASSERT_GE(b.x, 0.0f);
    ASSERT_GE(b.y, 0.0f);
    ASSERT_LE(b.x + b.y, 1.0f + 1e-6f);
    mean += glm::dvec2(b);
  }
  mean /= double(n);
  EXPECT_NEAR(mean.x, 1.0 / 3.0, 3e-3);  // the centroid
  EXPECT_NEAR(mean.y, 1.0 / 3.0, 3e-3);
}

TEST(Frame, IsOrthonormalForAnyNormal) {
  for (glm::vec3 n : {glm::vec3(0, 0, 1), glm::vec3(0, 0, -1), glm::vec3(1, 0, 0),
                      glm::normalize(glm::vec3(1, -2, 0.3f))}) {
    const Frame f(n);
    EXPECT_NEAR(glm::dot(f.tangent, f.bitangent), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::dot(f.tangent, f.normal), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::length(f.tangent), 1.0f, 1e-6f);
    EXPECT_NEAR(glm::length(f.bitangent), 1.0f, 1e-6f);
    const glm::vec3 v(0.2f, -0.5f, 0.7f);
    const glm::vec3 back = f.to_local(f.to_world(v));
    EXPECT_NEAR(glm::length(back - v), 0.0f, 1e-5f);
  }
}

// A 256 x 256 grid over [0,1)^2 with the square's edges, centre and axes exactly, then random
// points: where the concentric map switches octant, divides by zero or meets its corners.
template <class Check>
void for_test_points(const Check& check) {
  for (int j = 0; j <= 256; ++j)
    for (int i = 0; i <= 256; ++i)
      check(glm::vec2(std::min(float(i) / 256.0f, 0.99999994f),
                      std::min(float(j) / 256.0f, 0.99999994f)));
  Rng rng(3);
  for (int k = 0; k < 100'000; ++k) check(rng.next_2d());
}

TEST(SquareToCosineHemisphere, IsTheConcentricDiskLifted) {
  // Against square_to_disk (sincosf) lifted by Malley's method: the disk point to float
  // rounding. z = sqrt(1 - r^2) is ill-conditioned at the rim (a 1e-7 change of r^2 moves z by
  // 3e-4 there, in both maps alike), so z is compared squared.
  float worst_disk = 0.0f, worst_z2 = 0.0f;
  for_test_points([&](glm::vec2 u) {
    const glm::vec3 d = square_to_cosine_hemisphere(u);
    const glm::vec2 disk = square_to_disk(u);
    const float z2 = std::max(0.0f, 1.0f - glm::dot(disk, disk));
    worst_disk = std::max(worst_disk, glm::length(glm::vec2(d) - disk));
    worst_z2 = std::max(worst_z2, std::abs(d.z * d.z - z2));
    ASSERT_GE(d.z, 0.0f);
    ASSERT_NEAR(glm::length(d), 1.0f, 1e-6f);
  });
  EXPECT_LT(worst_disk, 1e-6f);
  EXPECT_LT(worst_z2, 1e-6f);
}

TEST(SquareToTriangle, IsHeitzsMapBitForBit) {
  // The branch-free map against the paper's two-case form.
  for_test_points([](glm::vec2 u) {
    float b0, b1;
    if (u.y > u.x) {
      b0 = u.x / 2.0f;
      b1 = u.y - b0;
    } else {
      b1 = u.y / 2.0f;
      b0 = u.x - b1;
    }
    const glm::vec2 b = square_to_triangle(u);
    ASSERT_EQ(b.x, b1);
    ASSERT_EQ(b.y, 1.0f - b0 - b1);
  });
}

}  // namespace
}  // namespace lb
