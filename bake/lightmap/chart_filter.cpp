#include "bake/lightmap/chart_filter.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstdint>
#include <span>

namespace lb {

std::vector<int> label_charts(int width, int height, const std::vector<double>& weight) {
  std::vector<int> label(weight.size(), -1);
  std::vector<size_t> stack;
  int next = 0;
  for (size_t start = 0; start < weight.size(); ++start) {
    if (!(weight[start] > 0.0) || label[start] >= 0) continue;
    label[start] = next;
    stack.push_back(start);
    while (!stack.empty()) {
      const size_t k = stack.back();
      stack.pop_back();
      const int i = int(k % size_t(width)), j = int(k / size_t(width));
      const int di[] = {1, -1, 0, 0}, dj[] = {0, 0, 1, -1};
      for (int d = 0; d < 4; ++d) {
        const int a = i + di[d], b = j + dj[d];
        if (a < 0 || b < 0 || a >= width || b >= height) continue;
        const size_t n = size_t(b) * size_t(width) + size_t(a);
        if (weight[n] > 0.0 && label[n] < 0) {
          label[n] = next;
          stack.push_back(n);
        }
      }
    }
    ++next;
  }
  return label;
}

namespace {

// Summed-area tables over one chart's bounding rectangle: the weight and the weighted values,
// counting only the nodes `counts(k)` admits (the chart's own, or some of them). The table
// lives in the caller's `storage`, reused table after table: a fresh one for each radius of
// each chart was mapped and zeroed by the kernel (half a room bake's page faults).
class ChartSums {
 public:
  // Weight, weighted values, and the first and second moments of the nodes' places (x, y:
  // node columns and rows from the table's corner) for ChartFit::mean_at_node's plane.
  struct Box {
    double w = 0.0;
    glm::dvec3 wv{0.0};
    double wx = 0.0, wy = 0.0, wxx = 0.0, wyy = 0.0, wxy = 0.0;
    glm::dvec3 wxv{0.0}, wyv{0.0};

    Box operator+(const Box& o) const {
      return {w + o.w, wv + o.wv, wx + o.wx, wy + o.wy, wxx + o.wxx, wyy + o.wyy, wxy + o.wxy,
              wxv + o.wxv, wyv + o.wyv};
    }
    Box operator-(const Box& o) const {
      return {w - o.w, wv - o.wv, wx - o.wx, wy - o.wy, wxx - o.wxx, wyy - o.wyy, wxy - o.wxy,
              wxv - o.wxv, wyv - o.wyv};
    }
  };

  template <class Counts>
  ChartSums(int width, int i0, int j0, int i1, int j1, const Counts& counts,
            const std::vector<vec3>& values, const std::vector<double>& weight,
            std::vector<Box>& storage)
      : i0_(i0), j0_(j0), i1_(i1), j1_(j1), stride_(i1 - i0 + 2), sums_(storage) {
    sums_.assign(size_t(stride_) * size_t(j1 - j0 + 2), Box{});
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        const size_t k = size_t(j) * size_t(width) + size_t(i);
        Box b;
        if (counts(k)) {
          const double w = weight[k], x = i - i0, y = j - j0;
          const glm::dvec3 wv = w * glm::dvec3(values[k]);
          b = {w, wv, w * x, w * y, w * x * x, w * y * y, w * x * y, x * wv, y * wv};
        }
        const Box& left = at(i - i0, j - j0 + 1);
        const Box& up = at(i - i0 + 1, j - j0);
        const Box& corner = at(i - i0, j - j0);
        Box& s = at(i - i0 + 1, j - j0 + 1);
        s.w = b.w + left.w + up.w - corner.w;
        s.wv = b.wv + left.wv + up.wv - corner.wv;
        s.wx = b.wx + left.wx + up.wx - corner.wx;
        s.wy = b.wy + left.wy + up.wy - corner.wy;
        s.wxx = b.wxx + left.wxx + up.wxx - corner.wxx;
        s.wyy = b.wyy + left.wyy + up.wyy - corner.wyy;
        s.wxy = b.wxy + left.wxy + up.wxy - corner.wxy;
        s.wxv = b.wxv + left.wxv + up.wxv - corner.wxv;
        s.wyv = b.wyv + left.wyv + up.wyv - corner.wyv;
      }
  }

  // The sums over the counted nodes within `radius` of (i, j).
  Box box(int i, int j, int radius) const {
    const int a0 = std::max(i - radius, i0_) - i0_, a1 = std::min(i + radius, i1_) - i0_ + 1;
    const int b0 = std::max(j - radius, j0_) - j0_, b1 = std::min(j + radius, j1_) - j0_ + 1;
    const Box &p = at(a1, b1), &q = at(a0, b1), &r = at(a1, b0), &s = at(a0, b0);
    return p - q - r + s;
  }

 private:
  Box& at(int a, int b) { return sums_[size_t(b) * size_t(stride_) + size_t(a)]; }
  const Box& at(int a, int b) const { return sums_[size_t(b) * size_t(stride_) + size_t(a)]; }
  int i0_, j0_, i1_, j1_, stride_;
  std::vector<Box>& sums_;
};

struct Chart {
  int i0, j0, i1, j1;
  std::vector<size_t> nodes;
};

std::vector<Chart> charts_of(int width, const std::vector<int>& label) {
  std::vector<Chart> charts;
  for (size_t k = 0; k < label.size(); ++k) {
    if (label[k] < 0) continue;
    const int i = int(k % size_t(width)), j = int(k / size_t(width));
    if (size_t(label[k]) >= charts.size()) charts.resize(size_t(label[k]) + 1, {i, j, i, j, {}});
    Chart& c = charts[size_t(label[k])];
    c.i0 = std::min(c.i0, i), c.j0 = std::min(c.j0, j);
    c.i1 = std::max(c.i1, i), c.j1 = std::max(c.j1, j);
    c.nodes.push_back(k);
  }
  return charts;
}

// Box `b`'s mean moved from its centroid to the node (x, y) along the slope of the weighted
// least-squares plane through the nodes of `wide`, the box twice as wide: the slope of b's own
// nodes, one-sided at a border, would carry their noise into the node several times over (it
// made the room's map 40% noisier). Where wide's nodes lie in a line or less, the mean.
glm::dvec3 mean_at_node(const ChartSums::Box& b, const ChartSums::Box& wide, double x, double y) {
  const glm::dvec3 mean = b.wv / b.w;
  const double cx = wide.wx / wide.w, cy = wide.wy / wide.w;
  const double sxx = wide.wxx - cx * wide.wx, syy = wide.wyy - cy * wide.wy;
  const double sxy = wide.wxy - cx * wide.wy;
  const glm::dvec3 sxv = wide.wxv - cx * wide.wv, syv = wide.wyv - cy * wide.wv;
  const double det = sxx * syy - sxy * sxy;
  if (!(det > 1e-9 * wide.w * wide.w)) return mean;
  const glm::dvec3 gx = (syy * sxv - sxy * syv) / det, gy = (sxx * syv - sxy * sxv) / det;
  return mean - gx * (b.wx / b.w - x) - gy * (b.wy / b.w - y);
}

}  // namespace

std::vector<vec3> chart_box_filter(int width, int height, const std::vector<vec3>& values,
                                   const std::vector<double>& weight, int radius) {
  return chart_box_filter(width, height, values, weight, std::vector<int>(values.size(), radius));
}

std::vector<vec3> chart_box_filter(int width, int height, const std::vector<vec3>& values,
                                   const std::vector<double>& weight,
                                   const std::vector<int>& radius) {
  std::vector<vec3> out = values;
  std::vector<vec3>* layers[] = {&out};
  chart_box_filter_in_place(width, height, layers, weight, radius);
  return out;
}

void chart_box_filter_in_place(int width, int height, std::span<std::vector<vec3>* const> layers,
                               const std::vector<double>& weight, const std::vector<int>& radius,
                               ChartFit fit) {
  const std::vector<int> label = label_charts(width, height, weight);
  const std::vector<Chart> charts = charts_of(width, label);
  // A chart reads only its own nodes and writes them once it has read them all, so the layers
  // can be filtered in place, charts in parallel; a layer at a time (a chart's table can span
  // most of the atlas).
  // Each thread's buffers, kept from chart to chart for this call (fresh ones were mapped and
  // zeroed by the kernel chart after chart).
  struct Scratch {
    std::vector<ChartSums::Box> sums, wide, table;
  };
  tbb::enumerable_thread_specific<Scratch> scratch;
  tbb::parallel_for(size_t(0), charts.size(), [&](size_t c) {
    const Chart& chart = charts[c];
    std::vector<int> radii;
    for (const size_t k : chart.nodes) radii.push_back(radius[k]);
    std::sort(radii.begin(), radii.end());
    radii.erase(std::unique(radii.begin(), radii.end()), radii.end());
    auto& [sums, wide, table] = scratch.local();
    sums.resize(chart.nodes.size());
    wide.resize(fit == ChartFit::mean_at_node ? chart.nodes.size() : 0);
    for (std::vector<vec3>* layer : layers) {
      // Node k sums, for each radius R present, the nodes of radius R within min(R, radius[k])
      // of it: one table at a time (memory: one table a chart, whatever the radii).
      std::fill(sums.begin(), sums.end(), ChartSums::Box{});
      std::fill(wide.begin(), wide.end(), ChartSums::Box{});
      for (const int r : radii) {
        const auto counts = [&](size_t k) { return label[k] == int(c) && radius[k] == r; };
        const ChartSums of_radius(width, chart.i0, chart.j0, chart.i1, chart.j1, counts, *layer,
                                  weight, table);
        for (size_t n = 0; n < chart.nodes.size(); ++n) {
          const size_t k = chart.nodes[n];
          const ChartSums::Box b = of_radius.box(int(k % size_t(width)), int(k / size_t(width)),
                                                 std::min(r, radius[k]));
          sums[n] = sums[n] + b;
          if (!wide.empty())
            wide[n] = wide[n] + of_radius.box(int(k % size_t(width)), int(k / size_t(width)),
                                              2 * std::min(r, radius[k]));
        }
      }
      for (size_t n = 0; n < chart.nodes.size(); ++n) {
        const size_t k = chart.nodes[n];
        const double x = int(k % size_t(width)) - chart.i0, y = int(k / size_t(width)) - chart.j0;
        (*layer)[k] = vec3(wide.empty() ? sums[n].wv / sums[n].w
                                        : mean_at_node(sums[n], wide[n], x, y));
      }
    }
  });
  // 0 outside every chart.
  for (size_t k = 0; k < label.size(); ++k)
    if (label[k] < 0)
      for (std::vector<vec3>* layer : layers) (*layer)[k] = vec3(0.0f);
}

}  // namespace lb
