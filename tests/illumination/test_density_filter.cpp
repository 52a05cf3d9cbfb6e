// The density filter (density_filter.h) against its definition summed tap by tap: with a
// uniform deposit density d every kernel has the radius R = sqrt(min_deposits / (pi d)), and each
// node's value is A_t sum_s w_ts P_s / sum_s w_ts A_s over its chart's nodes with
// w = 1 - |s - t|^2 / R^2 > 0, each chart then scaled back to its power before the filter.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "bake/illumination/atlas.h"
#include "bake/illumination/density_filter.h"
#include "bake/sampling.h"
#include "test_helpers.h"

namespace lb::illumination {
namespace {

TEST(DensityFilter, MatchesTheKernelSumTapByTap) {
  Scene scene;
  const int white = test::add_material(scene, Material{});
  scene.meshes.push_back(test::make_box({-2, -2, 0}, {2, 2, 2.5f}, white, true, "room"));
  scene.meshes.push_back(test::make_box({-0.5f, -0.5f, 0}, {0.5f, 0.5f, 0.7f}, white, false, "box"));
  AtlasParams atlas_params;
  atlas_params.texel_size = 0.05f;
  const Atlas atlas = build_atlas(scene, {true, true}, atlas_params);
  ASSERT_GT(atlas.charts.size(), 4u);
  const size_t nodes = size_t(atlas.width) * size_t(atlas.height);

  // Sparse speckle (one node in 7 lit) on uniform deposits: the radius a density of 0.1 deposits
  // a node gives for 16 deposits, 7.1 texels, so a kernel crosses chart borders and edges.
  std::vector<int> chart_of(nodes, -1);
  for (size_t c = 0; c < atlas.charts.size(); ++c) {
    const AtlasChart& chart = atlas.charts[c];
    const glm::ivec2 lo = glm::max(chart.offset - 1, glm::ivec2(0));
    const glm::ivec2 hi =
        glm::min(chart.offset + chart.size, glm::ivec2(atlas.width - 1, atlas.height - 1));
    for (int j = lo.y; j <= hi.y; ++j)
      for (int i = lo.x; i <= hi.x; ++i)
        if (atlas.valid[atlas.node_index(i, j)]) chart_of[atlas.node_index(i, j)] = int(c);
  }
  const double density = 0.1, min_deposits = 16.0;
  // The filter keeps radii as floats.
  const double radius = double(float(std::sqrt(min_deposits / (std::numbers::pi * density))));
  // Deposits on every node, also those outside the charts, so every box the filter counts
  // holds density deposits a node.
  const std::vector<double> deposits(nodes, density);
  std::vector<glm::dvec3> power(nodes, glm::dvec3(0.0));
  Rng rng(40);
  for (size_t k = 0; k < nodes; ++k) {
    if (chart_of[k] < 0) continue;
    if (rng.next_float() < 1.0f / 7.0f)
      power[k] = glm::dvec3(rng.next_float(), rng.next_float(), 0.5 * rng.next_float());
  }

  std::vector<glm::dvec3> filtered = power;
  filter_by_density(atlas, deposits, min_deposits, 8, filtered);

  // The definition, tap by tap, then each chart scaled back to its power.
  std::vector<glm::dvec3> expected(nodes, glm::dvec3(0.0));
  std::vector<glm::dvec3> before(atlas.charts.size(), glm::dvec3(0.0));
  std::vector<glm::dvec3> after(atlas.charts.size(), glm::dvec3(0.0));
  const int reach = int(std::ceil(radius));
  for (int j = 0; j < atlas.height; ++j)
    for (int i = 0; i < atlas.width; ++i) {
      const size_t t = atlas.node_index(i, j);
      if (chart_of[t] < 0) continue;
      glm::dvec3 sum(0.0);
      double area = 0.0;
      for (int y = std::max(0, j - reach); y <= std::min(atlas.height - 1, j + reach); ++y)
        for (int x = std::max(0, i - reach); x <= std::min(atlas.width - 1, i + reach); ++x) {
          const size_t s = atlas.node_index(x, y);
          const double w = 1.0 - double((x - i) * (x - i) + (y - j) * (y - j)) / (radius * radius);
          if (chart_of[s] != chart_of[t] || !(w > 0.0)) continue;
          sum += w * power[s];
          area += w * double(atlas.texel_area[s]);
        }
      expected[t] = sum * (double(atlas.texel_area[t]) / area);
      before[size_t(chart_of[t])] += power[t];
      after[size_t(chart_of[t])] += expected[t];
    }
  double largest = 0.0, worst = 0.0;
  for (size_t k = 0; k < nodes; ++k) {
    if (chart_of[k] < 0) continue;
    const glm::dvec3 b = before[size_t(chart_of[k])], a = after[size_t(chart_of[k])];
    for (int ch = 0; ch < 3; ++ch) {
      const double e = a[ch] > 0.0 ? expected[k][ch] * b[ch] / a[ch] : 0.0;
      largest = std::max(largest, e);
      worst = std::max(worst, std::abs(filtered[k][ch] - e));
      ASSERT_GE(filtered[k][ch], 0.0);
    }
  }
  ASSERT_GT(largest, 0.0);
  // Measured 1.1e-15 of the largest value (the sums run in another order than tap by tap).
  EXPECT_LT(worst, 1e-12 * largest) << "worst difference " << worst << " of " << largest;
  std::printf("filter vs tap-by-tap sum: worst difference %.3g of the largest value\n",
              worst / largest);
}

}  // namespace
}  // namespace lb::illumination
