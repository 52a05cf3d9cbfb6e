#include "bake/illumination/density_filter.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>

namespace lb::illumination {

namespace {

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
  // The kernel is Epanechnikov's, 1 - d^2 / R^2 for node offsets d^2 = dx^2 + dy^2 < R^2
  // (texels). Along a kernel's row the taps are an interval of the chart's row and the weight
  // is a quadratic in the column, so a row's sums come from prefix sums of
  // v, x v and x^2 v along the chart's rows (x from the chart's left edge, keeping the sums
  // small): O(R) per node instead of O(R^2). Prefix rows are built per band of rows, so memory
  // stays at a few rows of a chart. A row without a lit node adds exactly 0, as tap by tap;
  // elsewhere the double sums differ from the tap-by-tap order in the last bits only.
  struct Prefix {
    glm::dvec3 p0{0.0}, p1{0.0}, p2{0.0};  // power: sum v, sum x v, sum x^2 v
    double a0 = 0.0, a1 = 0.0, a2 = 0.0;   // node area, likewise
    int32_t lit = 0;                       // lit nodes
  };
  std::vector<glm::dvec3> filtered = node_power;
  constexpr int kBand = 32;
  for (size_t c = 0; c < atlas.charts.size(); ++c) {
    if (!chart_lit[c]) continue;
    const glm::ivec4 r4 = rect[c];
    const int w = r4.z - r4.x + 1, h = r4.w - r4.y + 1;
    const size_t row_length = size_t(w) + 1;
    tbb::parallel_for(0, (h + kBand - 1) / kBand, [&](int band) {
      const int b0 = band * kBand, b1 = std::min(h, b0 + kBand);  // the band's rows
      const int q0 = std::max(0, b0 - max_radius), q1 = std::min(h, b1 + max_radius);
      thread_local std::vector<Prefix> prefix;
      prefix.assign(row_length * size_t(q1 - q0), Prefix{});
      for (int y = q0; y < q1; ++y) {
        Prefix* row = prefix.data() + size_t(y - q0) * row_length;
        for (int x = 0; x < w; ++x) {
          const size_t s = atlas.node_index(r4.x + x, r4.y + y);
          Prefix next = row[x];
          if (chart_of[s] == int32_t(c)) {
            const double fx = double(x), fx2 = fx * fx, a = double(atlas.texel_area[s]);
            const glm::dvec3 v = node_power[s];
            next.p0 += v, next.p1 += fx * v, next.p2 += fx2 * v;
            next.a0 += a, next.a1 += fx * a, next.a2 += fx2 * a;
            next.lit += lit(v) ? 1 : 0;
          }
          row[x + 1] = next;
        }
      }
      for (int y = b0; y < b1; ++y)
        for (int x = 0; x < w; ++x) {
          const size_t t = atlas.node_index(r4.x + x, r4.y + y);
          const float r = radius[t];
          if (r == 0.0f || chart_of[t] != int32_t(c)) continue;
          const int reach = int(std::ceil(r)) - 1;  // offsets with |d| < R
          const double rr = double(r) * double(r), inverse_rr = 1.0 / rr, fi = double(x);
          glm::dvec3 power(0.0);
          double area = 0.0;
          for (int dy = -reach; dy <= reach; ++dy) {
            if (y + dy < 0 || y + dy >= h) continue;
            int half = reach;  // the row's taps of positive weight: |dx| <= half
            while (half >= 0 && !(double(half * half + dy * dy) < rr)) --half;
            if (half < 0) continue;
            const Prefix* row = prefix.data() + size_t(y + dy - q0) * row_length;
            const Prefix& lo = row[std::max(x - half, 0)];
            const Prefix& hi = row[std::min(x + half, w - 1) + 1];
            // sum over the taps of (base - (x_s - x)^2 / R^2) v_s
            const double base = 1.0 - double(dy * dy) * inverse_rr;
            const double s0 = hi.a0 - lo.a0, s1 = hi.a1 - lo.a1, s2 = hi.a2 - lo.a2;
            area += base * s0 - (s2 - 2.0 * fi * s1 + fi * fi * s0) * inverse_rr;
            if (hi.lit == lo.lit) continue;
            const glm::dvec3 v0 = hi.p0 - lo.p0, v1 = hi.p1 - lo.p1, v2 = hi.p2 - lo.p2;
            power += base * v0 - (v2 - 2.0 * fi * v1 + fi * fi * v0) * inverse_rr;
          }
          // Rounding must not make light negative; area > 0: t itself.
          filtered[t] = glm::max(power, glm::dvec3(0.0)) * (double(atlas.texel_area[t]) / area);
        }
    });
  }
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
