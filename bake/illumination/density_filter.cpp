#include "bake/illumination/density_filter.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>

namespace lb::illumination {

namespace {

// Epanechnikov weight at squared distance d2 (texels^2) for support radius R: 0 outside.
double kernel(int d2, float radius) {
  return std::max(0.0, 1.0 - double(d2) / (double(radius) * double(radius)));
}

bool lit(const glm::dvec3& p) {
  return p.x != 0.0 || p.y != 0.0 || p.z != 0.0;
}

}  // namespace

DensityFilterStats filter_by_density(const Atlas& atlas, const std::vector<double>& node_deposits,
                                     double min_deposits, int max_radius,
                                     std::vector<glm::dvec3>& node_power,
                                     const std::vector<bool>& raw_meshes) {
  DensityFilterStats stats;
  const int width = atlas.width, height = atlas.height;
  const size_t nodes = size_t(width) * size_t(height);
  if (width <= 0 || height <= 0 || max_radius <= 0 || !(min_deposits > 0.0) ||
      node_power.size() != nodes || node_deposits.size() != nodes)
    return stats;

  // Each chart's node rectangle (w + 2 nodes a side, atlas.h) holds only its own valid nodes.
  std::vector<int32_t> chart_of(nodes, -1);
  std::vector<glm::ivec4> rect(atlas.charts.size());  // lo.x, lo.y, hi.x, hi.y inclusive
  for (size_t c = 0; c < atlas.charts.size(); ++c) {
    const AtlasChart& chart = atlas.charts[c];
    const glm::ivec2 lo = glm::max(chart.offset - 1, glm::ivec2(0));
    const glm::ivec2 hi = glm::min(chart.offset + chart.size, glm::ivec2(width - 1, height - 1));
    rect[c] = {lo.x, lo.y, hi.x, hi.y};
    for (int j = lo.y; j <= hi.y; ++j)
      for (int i = lo.x; i <= hi.x; ++i)
        if (atlas.valid[atlas.node_index(i, j)]) chart_of[atlas.node_index(i, j)] = int32_t(c);
  }

  // Summed-area table of the deposits: the count in any box in O(1).
  const size_t stride = size_t(width) + 1;
  std::vector<double> sat(stride * (size_t(height) + 1), 0.0);
  for (int j = 0; j < height; ++j)
    for (int i = 0; i < width; ++i)
      sat[size_t(j + 1) * stride + size_t(i + 1)] =
          node_deposits[atlas.node_index(i, j)] + sat[size_t(j) * stride + size_t(i + 1)] +
          sat[size_t(j + 1) * stride + size_t(i)] - sat[size_t(j) * stride + size_t(i)];
  auto count_in = [&](int x0, int y0, int x1, int y1) {
    return sat[size_t(y1 + 1) * stride + size_t(x1 + 1)] -
           sat[size_t(y0) * stride + size_t(x1 + 1)] - sat[size_t(y1 + 1) * stride + size_t(x0)] +
           sat[size_t(y0) * stride + size_t(x0)];
  };

  // ---- per node: the kernel radius from the local deposit density -----------------------------
  // The smallest box of half-width r around the node (clipped to its chart) that holds
  // min_deposits gives the local density rho (deposits per node); the kernel's radius is then
  // R = sqrt(min_deposits / (pi rho)), the disk that holds min_deposits at that density. R is
  // continuous, so neighbours of similar density get similar kernels (an integer radius jumps
  // where a count crosses the threshold and prints that noise back as blotches). R <= 1
  // reaches no other node: the node keeps its value.
  std::vector<uint8_t> chart_lit(atlas.charts.size(), 0);
  for (size_t k = 0; k < nodes; ++k)
    if (chart_of[k] >= 0 && lit(node_power[k])) chart_lit[size_t(chart_of[k])] = 1;
  for (size_t c = 0; c < atlas.charts.size(); ++c) {  // kept raw: as if unlit, left alone
    const int mesh = atlas.charts[c].mesh;
    if (mesh >= 0 && size_t(mesh) < raw_meshes.size() && raw_meshes[size_t(mesh)]) chart_lit[c] = 0;
  }
  std::vector<float> radius(nodes, 0.0f);
  tbb::parallel_for(0, height, [&](int j) {
    for (int i = 0; i < width; ++i) {
      const size_t t = atlas.node_index(i, j);
      const int32_t c = chart_of[t];
      if (c < 0 || !chart_lit[size_t(c)]) continue;
      const glm::ivec4 r4 = rect[size_t(c)];
      double count = 0.0;
      int boxed = 1;
      for (int r = 0;; ++r) {
        const int x0 = std::max(i - r, r4.x), y0 = std::max(j - r, r4.y);
        const int x1 = std::min(i + r, r4.z), y1 = std::min(j + r, r4.w);
        count = count_in(x0, y0, x1, y1);
        boxed = (x1 - x0 + 1) * (y1 - y0 + 1);
        if (count >= min_deposits || r >= max_radius) break;
      }
      if (!(count > 0.0)) continue;  // no deposit within reach: nothing to gather
      const double rho = count / double(boxed);
      const double big_r =
          std::min(double(max_radius), std::sqrt(min_deposits / (std::numbers::pi * rho)));
      if (big_r > 1.0) radius[t] = float(big_r);
    }
  });

  // ---- gather: radiance averaged over the kernel, weighted by node area ----------------------
  // value_t = A_t * sum_s w_ts P_s / sum_s w_ts A_s: a uniform radiance stays exactly uniform,
  // at chart borders and on partial nodes too. Each chart's total is then scaled back to its
  // power before the filter, so no power is made or lost (per chart, to rounding).
  // A kernel over no lit node gives exactly 0 (its power sum adds +0 only, its area sum is
  // >= the node's own area), so it is skipped; the others take their weights from a table of
  // the (reach + 1)^2 distinct offsets, the very values kernel() gives, summed in the same
  // order: the same bits as a division per offset (bench_illumination /64, docs/illumination.md).
  std::vector<int32_t> lit_sat(stride * (size_t(height) + 1), 0);  // lit nodes in a box, O(1)
  for (int j = 0; j < height; ++j)
    for (int i = 0; i < width; ++i) {
      lit_sat[size_t(j + 1) * stride + size_t(i + 1)] =
          (lit(node_power[atlas.node_index(i, j)]) ? 1 : 0) + lit_sat[size_t(j) * stride + size_t(i + 1)] +
          lit_sat[size_t(j + 1) * stride + size_t(i)] - lit_sat[size_t(j) * stride + size_t(i)];
    }
  std::vector<glm::dvec3> filtered = node_power;
  tbb::parallel_for(0, height, [&](int j) {
    for (int i = 0; i < width; ++i) {
      const size_t t = atlas.node_index(i, j);
      const float r = radius[t];
      if (r == 0.0f) continue;
      const int32_t c = chart_of[t];
      const glm::ivec4 r4 = rect[size_t(c)];
      const int reach = int(std::ceil(r)) - 1;  // offsets with |d| < R
      const int x0 = std::max(i - reach, r4.x), x1 = std::min(i + reach, r4.z);
      const int y0 = std::max(j - reach, r4.y), y1 = std::min(j + reach, r4.w);
      const int32_t lit_in_box =
          lit_sat[size_t(y1 + 1) * stride + size_t(x1 + 1)] -
          lit_sat[size_t(y0) * stride + size_t(x1 + 1)] -
          lit_sat[size_t(y1 + 1) * stride + size_t(x0)] + lit_sat[size_t(y0) * stride + size_t(x0)];
      if (lit_in_box == 0 && atlas.texel_area[t] > 0.0f) {  // 0 times a finite ratio
        filtered[t] = glm::dvec3(0.0);
        continue;
      }
      thread_local std::vector<double> weight;  // [|dy| * side + |dx|]
      const int side = reach + 1;
      weight.resize(size_t(side) * size_t(side));
      for (int dy = 0; dy < side; ++dy)
        for (int dx = 0; dx < side; ++dx)
          weight[size_t(dy * side + dx)] = kernel(dx * dx + dy * dy, r);
      glm::dvec3 power(0.0);
      double area = 0.0;
      for (int y = y0; y <= y1; ++y) {
        const double* row = weight.data() + size_t(std::abs(y - j) * side);
        for (int x = x0; x <= x1; ++x) {
          const size_t s = atlas.node_index(x, y);
          if (chart_of[s] != c) continue;
          const double w = row[std::abs(x - i)];
          power += w * node_power[s];
          area += w * double(atlas.texel_area[s]);
        }
      }
      filtered[t] = power * (double(atlas.texel_area[t]) / area);  // area > 0: t itself
    }
  });
  std::vector<glm::dvec3> before(atlas.charts.size(), glm::dvec3(0.0)),
      after(atlas.charts.size(), glm::dvec3(0.0));
  for (size_t k = 0; k < nodes; ++k) {
    if (chart_of[k] < 0 || !chart_lit[size_t(chart_of[k])]) continue;
    before[size_t(chart_of[k])] += node_power[k];
    after[size_t(chart_of[k])] += filtered[k];
    if (lit(node_power[k])) {
      ++stats.nodes_lit;
      stats.nodes_spread += radius[k] > 0.0f;
      const double p = node_power[k].x + node_power[k].y + node_power[k].z;
      stats.mean_radius += double(radius[k]) * p;
      stats.power += p;
    }
  }
  if (stats.power > 0.0) stats.mean_radius /= stats.power;
  for (size_t k = 0; k < nodes; ++k) {
    if (chart_of[k] < 0 || !chart_lit[size_t(chart_of[k])]) continue;
    const glm::dvec3 b = before[size_t(chart_of[k])], a = after[size_t(chart_of[k])];
    for (int ch = 0; ch < 3; ++ch) filtered[k][ch] *= a[ch] > 0.0 ? b[ch] / a[ch] : 0.0;
  }
  node_power.swap(filtered);
  return stats;
}

}  // namespace lb::illumination
