// The chart filter (bake/lightmap/chart_filter.h) against a plain loop over each box: per-chart
// summed-area tables must give the same means, never mixing charts that a box overlaps, with
// one radius and with a radius per node; and the mean moved to the node against a linear
// field's closed form.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <tuple>

#include "bake/lightmap/chart_filter.h"

namespace lb {
namespace {

// The definition, written out: the weight-averaged mean over the nodes n of the same chart
// within min(radius[k], radius[n]) of node k.
std::vector<vec3> box_by_hand(int width, int height, const std::vector<vec3>& values,
                              const std::vector<double>& weight, const std::vector<int>& label,
                              const std::vector<int>& radius) {
  std::vector<vec3> out(values.size(), vec3(0.0f));
  for (int j = 0; j < height; ++j)
    for (int i = 0; i < width; ++i) {
      const size_t k = size_t(j * width + i);
      if (label[k] < 0) continue;
      glm::dvec3 sum(0.0);
      double total = 0.0;
      for (int b = 0; b < height; ++b)
        for (int a = 0; a < width; ++a) {
          const size_t n = size_t(b * width + a);
          const int reach = std::min(radius[k], radius[n]);
          if (label[n] != label[k] || std::abs(a - i) > reach || std::abs(b - j) > reach)
            continue;
          sum += weight[n] * glm::dvec3(values[n]);
          total += weight[n];
        }
      out[k] = vec3(sum / total);
    }
  return out;
}

// Three charts one texel apart: an L (its box overlaps the others' rectangles), a square
// inside the L's corner and a ring around an empty hole; random weights and values.
struct Charts {
  static constexpr int width = 40, height = 30;
  std::vector<double> weight = std::vector<double>(size_t(width * height), 0.0);
  std::vector<vec3> values = std::vector<vec3>(weight.size(), vec3(0.0f));
  std::vector<int> label;

  Charts() {
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
    label = label_charts(width, height, weight);
  }
};

double largest_difference(const std::vector<vec3>& a, const std::vector<vec3>& b) {
  double worst = 0.0;
  for (size_t k = 0; k < a.size(); ++k)
    for (int c = 0; c < 3; ++c) worst = std::max(worst, double(std::abs(a[k][c] - b[k][c])));
  return worst;
}

TEST(ChartFilter, SummedAreaBoxesEqualTheBoxesByHand) {
  const Charts charts;
  const int width = charts.width, height = charts.height;
  const auto& [weight, values, label] = std::tie(charts.weight, charts.values, charts.label);
  EXPECT_EQ(*std::max_element(label.begin(), label.end()), 2);  // 3 charts
  for (const int radius : {0, 1, 3, 6, 10, 16}) {
    const std::vector<vec3> fast = chart_box_filter(width, height, values, weight, radius);
    const std::vector<vec3> slow =
        box_by_hand(width, height, values, weight, label, std::vector<int>(weight.size(), radius));
    // Measured at most 1.2e-7 (a float ulp of values up to 2); bound 1e-6.
    EXPECT_LT(largest_difference(fast, slow), 1e-6) << "radius " << radius;
  }
}

// A radius per node (the soft-light map's proximity boxes): the symmetric kernel by hand, a
// node of radius 0 keeps its own value, and a constant field stays constant.
TEST(ChartFilter, PerNodeRadiiAverageWithinBothRadii) {
  const Charts charts;
  const int width = charts.width, height = charts.height;
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> pick(0, 12);
  std::vector<int> radius(charts.weight.size());
  for (int& r : radius) r = pick(rng);
  const std::vector<vec3> fast =
      chart_box_filter(width, height, charts.values, charts.weight, radius);
  const std::vector<vec3> slow =
      box_by_hand(width, height, charts.values, charts.weight, charts.label, radius);
  const double worst = largest_difference(fast, slow);
  std::printf("per-node radii: largest difference from the definition %.3g\n", worst);
  // Measured 0 (the same sums in another order would differ by float ulps); bound 1e-6.
  EXPECT_LT(worst, 1e-6);
  for (size_t k = 0; k < radius.size(); ++k)
    if (radius[k] == 0 && charts.weight[k] > 0.0) {
      EXPECT_EQ(fast[k], charts.values[k]) << k;
    }

  const std::vector<vec3> constant(charts.values.size(), vec3(0.25f, -0.5f, 1.5f));
  const std::vector<vec3> flat = chart_box_filter(width, height, constant, charts.weight, radius);
  for (size_t k = 0; k < flat.size(); ++k)
    if (charts.weight[k] > 0.0) {
      EXPECT_LT(largest_difference({flat[k]}, {constant[k]}), 1e-6) << k;
    }
}

// A linear field (the first-order change of the light towards a crease) on the three charts,
// random weights and radii: the plain mean is off at the charts' borders and beside narrower
// neighbours, by the slope times the box's centroid's distance from the node; the mean moved to
// the node is the field there. A constant field stays constant either way.
TEST(ChartFilter, MeanAtNodeHoldsALinearFieldAtBordersAndBesideNarrowerRadii) {
  const Charts charts;
  const int width = charts.width, height = charts.height;
  std::mt19937 rng(13);
  std::uniform_int_distribution<int> pick(0, 6);
  std::vector<int> radius(charts.weight.size());
  for (int& r : radius) r = pick(rng);
  const auto field = [](int i, int j) {
    return vec3(0.5f + 0.05f * float(i), 1.0f - 0.02f * float(j),
                0.3f + 0.01f * float(i) + 0.03f * float(j));
  };
  std::vector<vec3> linear(charts.weight.size(), vec3(0.0f));
  for (int j = 0; j < height; ++j)
    for (int i = 0; i < width; ++i)
      if (charts.weight[size_t(j * width + i)] > 0.0) linear[size_t(j * width + i)] = field(i, j);
  std::vector<vec3> mean = linear, moved = linear;
  std::vector<vec3>* mean_layers[] = {&mean};
  std::vector<vec3>* moved_layers[] = {&moved};
  chart_box_filter_in_place(width, height, mean_layers, charts.weight, radius, ChartFit::mean);
  chart_box_filter_in_place(width, height, moved_layers, charts.weight, radius,
                            ChartFit::mean_at_node);
  const double mean_error = largest_difference(mean, linear);
  const double moved_error = largest_difference(moved, linear);
  std::printf("linear field: largest error of the mean %.3g, of the mean at the node %.3g\n",
              mean_error, moved_error);
  // The mean: up to the slope (0.05 a texel) times a centroid up to ~3 texels off, 0.1 or so;
  // the moved mean exact but for rounding (float values up to 2.5, double sums): bound 1e-5.
  EXPECT_GT(mean_error, 0.05);
  EXPECT_LT(moved_error, 1e-5);

  std::vector<vec3> flat(charts.weight.size(), vec3(0.25f, -0.5f, 1.5f));
  std::vector<vec3>* flat_layers[] = {&flat};
  chart_box_filter_in_place(width, height, flat_layers, charts.weight, radius,
                            ChartFit::mean_at_node);
  for (size_t k = 0; k < flat.size(); ++k)
    if (charts.weight[k] > 0.0) {
      EXPECT_LT(largest_difference({flat[k]}, {vec3(0.25f, -0.5f, 1.5f)}), 1e-6) << k;
    }
}

}  // namespace
}  // namespace lb
