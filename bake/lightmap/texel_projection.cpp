#include "bake/lightmap/texel_projection.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace lb {

namespace {

// The Gram matrix of a cell's four corner tents over its points, upper triangle row by row:
// (00 01 02 03 11 12 13 22 23 33). Corner k is node (i + k % 2, j + k / 2), as in fill_texels.
using CellGram = std::array<double, 10>;

constexpr int gram_index(int k, int l) {
  if (k > l) std::swap(k, l);
  constexpr int row_start[4] = {0, 4, 7, 9};
  return row_start[k] + (l - k);
}

CellGram cell_gram(std::span<const FootprintSample> samples) {
  CellGram g{};
  for (const FootprintSample& s : samples) {
    const double x = s.in_cell.x, y = s.in_cell.y;
    const double tent[4] = {(1 - x) * (1 - y), x * (1 - y), (1 - x) * y, x * y};
    for (int k = 0; k < 4; ++k)
      for (int l = k; l < 4; ++l) g[size_t(gram_index(k, l))] += double(s.area) * tent[k] * tent[l];
  }
  return g;
}

// M (+ the ridge) as a gather over each node's four cells, so every node's product is summed in
// one fixed order.
class TentSystem {
 public:
  TentSystem(int width, int height, std::vector<int32_t> slot, std::vector<CellGram> grams,
             double ridge)
      : width_(width), height_(height), slot_(std::move(slot)), grams_(std::move(grams)) {
    weight_.assign(size_t(width) * size_t(height), 0.0);
    diagonal_.assign(weight_.size(), 0.0);
    for_each_node([&](size_t node, int i, int j) {
      for_each_cell(i, j, [&](const CellGram& g, int k, int l, size_t) {
        weight_[node] += g[size_t(gram_index(k, l))];
        if (l == k) diagonal_[node] += g[size_t(gram_index(k, k))];
      });
      diagonal_[node] += ridge * weight_[node];
    });
    ridge_ = ridge;
  }

  const std::vector<double>& weight() const { return weight_; }
  const std::vector<double>& diagonal() const { return diagonal_; }

  // y = (M + ridge diag(weight)) x
  void multiply(const std::vector<double>& x, std::vector<double>& y) const {
    for_each_node([&](size_t node, int i, int j) {
      double sum = ridge_ * weight_[node] * x[node];
      for_each_cell(i, j, [&](const CellGram& g, int k, int l, size_t other) {
        sum += g[size_t(gram_index(k, l))] * x[other];
      });
      y[node] = sum;
    });
  }

 private:
  template <class F>
  void for_each_node(F&& f) const {
    tbb::parallel_for(0, height_, [&](int j) {
      for (int i = 0; i < width_; ++i) f(size_t(j) * size_t(width_) + size_t(i), i, j);
    });
  }
  // f(gram, k, l, node_l) for each cell around node (i, j) (where the node is corner k) and
  // each of that cell's corners l.
  template <class F>
  void for_each_cell(int i, int j, F&& f) const {
    const int ci[4] = {i - 1, i, i - 1, i}, cj[4] = {j - 1, j - 1, j, j};
    const int corner[4] = {3, 2, 1, 0};
    for (int c = 0; c < 4; ++c) {
      if (ci[c] < 0 || cj[c] < 0 || ci[c] >= width_ || cj[c] >= height_) continue;
      const int32_t s = slot_[size_t(cj[c]) * size_t(width_) + size_t(ci[c])];
      if (s < 0) continue;
      for (int l = 0; l < 4; ++l) {
        const int ni = ci[c] + l % 2, nj = cj[c] + l / 2;
        if (ni >= width_ || nj >= height_) continue;  // no surface reaches past the last node
        f(grams_[size_t(s)], corner[c], l, size_t(nj) * size_t(width_) + size_t(ni));
      }
    }
  }

  int width_, height_;
  std::vector<int32_t> slot_;  // per cell, its Gram matrix's index, -1 without points
  std::vector<CellGram> grams_;
  std::vector<double> weight_, diagonal_;
  double ridge_ = 0.0;
};

double dot(const std::vector<double>& a, const std::vector<double>& b) {
  double sum = 0.0;  // in index order: the same bits whatever the thread count
  for (size_t k = 0; k < a.size(); ++k) sum += a[k] * b[k];
  return sum;
}

// Jacobi-preconditioned conjugate gradients on the nodes with weight, from x's start.
void solve(const TentSystem& system, const std::vector<double>& rhs, std::vector<double>& x,
           const ProjectionParams& params, const Progress& progress, ProjectionStats& stats) {
  const size_t n = x.size();
  const std::vector<double>& diagonal = system.diagonal();
  std::vector<double> r(n), z(n), p(n), ap(n);
  system.multiply(x, ap);
  for (size_t k = 0; k < n; ++k) r[k] = diagonal[k] > 0.0 ? rhs[k] - ap[k] : 0.0;
  const double rhs_norm = std::sqrt(dot(rhs, rhs));
  if (!(rhs_norm > 0.0)) return;
  for (size_t k = 0; k < n; ++k) z[k] = diagonal[k] > 0.0 ? r[k] / diagonal[k] : 0.0;
  p = z;
  double rz = dot(r, z);
  int iteration = 0;
  double residual = std::sqrt(dot(r, r)) / rhs_norm;
  for (; iteration < params.max_iterations && residual > params.tolerance; ++iteration) {
    progress.throw_if_cancelled();
    system.multiply(p, ap);
    const double pap = dot(p, ap);
    if (!(pap > 0.0)) break;
    const double alpha = rz / pap;
    for (size_t k = 0; k < n; ++k) x[k] += alpha * p[k], r[k] -= alpha * ap[k];
    for (size_t k = 0; k < n; ++k) z[k] = diagonal[k] > 0.0 ? r[k] / diagonal[k] : 0.0;
    const double rz_next = dot(r, z);
    const double beta = rz_next / rz;
    rz = rz_next;
    for (size_t k = 0; k < n; ++k) p[k] = z[k] + beta * p[k];
    residual = std::sqrt(dot(r, r)) / rhs_norm;
  }
  stats.iterations = std::max(stats.iterations, iteration);
  stats.residual = std::max(stats.residual, residual);
}

}  // namespace

std::vector<vec3> project_to_bilinear(const TexelFootprints& footprints,
                                      const FillTexelsParams& points, std::span<const vec3> means,
                                      const ProjectionParams& params, const Progress& progress,
                                      ProjectionStats* stats_out) {
  const int width = footprints.width(), height = footprints.height();
  const size_t nodes = size_t(width) * size_t(height);
  std::vector<vec3> out(means.begin(), means.end());
  if (means.size() != nodes || nodes == 0) return out;

  // The Gram matrices of the cells, from the same points fill_texels made (no estimates); by
  // row, then joined in row order.
  std::vector<std::vector<std::pair<size_t, CellGram>>> rows(static_cast<size_t>(height));
  tbb::parallel_for(0, height, [&](int j) {
    std::vector<FootprintSample> samples;
    for (int i = 0; i < width; ++i) {
      const size_t cell = size_t(j) * size_t(width) + size_t(i);
      if (footprints.cell_empty(cell)) continue;
      samples.clear();
      footprints.cell_samples(i, j, points.rule, std::max(1, points.side), points.seed, samples);
      drop_hidden_samples(samples, points.hidden_triangles);
      if (!samples.empty()) rows[size_t(j)].emplace_back(cell, cell_gram(samples));
    }
  });
  progress.throw_if_cancelled();
  std::vector<int32_t> slot(nodes, -1);
  std::vector<CellGram> grams;
  for (auto& row : rows) {
    for (const auto& [cell, gram] : row) {
      slot[cell] = int32_t(grams.size());
      grams.push_back(gram);
    }
    row = {};
  }
  const TentSystem system(width, height, std::move(slot), std::move(grams), params.ridge);

  ProjectionStats stats;
  std::vector<double> rhs(nodes), x(nodes);
  std::vector<uint8_t> clamped(nodes, 0);
  for (int c = 0; c < 3; ++c) {
    for (size_t k = 0; k < nodes; ++k) {
      const double w = system.weight()[k];
      // b_n = mean_n weight_n, plus the ridge's pull towards the mean.
      rhs[k] = w > 0.0 ? (1.0 + double(params.ridge)) * w * double(means[k][c]) : 0.0;
      x[k] = w > 0.0 ? double(means[k][c]) : 0.0;
    }
    solve(system, rhs, x, params, progress, stats);
    for (size_t k = 0; k < nodes; ++k) {
      if (!(system.weight()[k] > 0.0)) continue;
      clamped[k] |= x[k] < 0.0;
      out[k][c] = float(std::max(x[k], 0.0));
    }
  }
  stats.clamped_nodes = size_t(std::count(clamped.begin(), clamped.end(), uint8_t(1)));
  if (stats_out) *stats_out = stats;
  return out;
}

}  // namespace lb
