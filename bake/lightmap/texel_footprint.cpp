#include "bake/lightmap/texel_footprint.h"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <mutex>
#include <stdexcept>
#include <string>

#include "bake/accel.h"
#include "bake/clip_polygon.h"
#include "bake/contact_cuts.h"
#include "bake/sampling.h"

namespace lb {

namespace {

// A triangle in node space (node (i, j) at integer coordinates) and what maps it back.
struct NodeSpaceTriangle {
  vec2 q[3];
  float inverse_det = 0.0f;     // of the edge matrix (q1 - q0, q2 - q0)
  double world_per_cell = 0.0;  // m^2 of surface per unit of node-space area
};

bool to_node_space(const Mesh& mesh, uint32_t triangle, int width, int height,
                   NodeSpaceTriangle& out) {
  const uvec3 tri = mesh.triangles[triangle];
  const vec2 scale{float(width), float(height)};
  for (int k = 0; k < 3; ++k) out.q[k] = mesh.lightmap_uvs[tri[k]] * scale - 0.5f;
  const vec2 e1 = out.q[1] - out.q[0], e2 = out.q[2] - out.q[0];
  const double det = double(e1.x) * e2.y - double(e1.y) * e2.x;
  const double world = triangle_area(mesh, triangle);
  if (!(std::abs(det) > 0.0) || !(world > 0.0)) return false;
  out.inverse_det = float(1.0 / det);
  out.world_per_cell = world / (0.5 * std::abs(det));
  return true;
}

// (b1, b2) of node-space point p.
vec2 barycentric_of(const NodeSpaceTriangle& t, vec2 p) {
  const vec2 e1 = t.q[1] - t.q[0], e2 = t.q[2] - t.q[0], d = p - t.q[0];
  return {(d.x * e2.y - d.y * e2.x) * t.inverse_det, (e1.x * d.y - e1.y * d.x) * t.inverse_det};
}

// Radon's 7-point rule on a triangle, exact for polynomials of degree <= 5: barycentric
// points and weights (summing to 1).
struct QuadraturePoint {
  float b[3];
  float weight;
};
const std::array<QuadraturePoint, 7>& radon7() {
  static const std::array<QuadraturePoint, 7> rule = [] {
    const double s = std::sqrt(15.0);
    const double a1 = (6.0 - s) / 21.0, b1 = (9.0 + 2.0 * s) / 21.0, w1 = (155.0 - s) / 1200.0;
    const double a2 = (6.0 + s) / 21.0, b2 = (9.0 - 2.0 * s) / 21.0, w2 = (155.0 + s) / 1200.0;
    auto f = [](double v) { return float(v); };
    return std::array<QuadraturePoint, 7>{{
        {{f(1.0 / 3), f(1.0 / 3), f(1.0 / 3)}, f(9.0 / 40)},
        {{f(a1), f(a1), f(b1)}, f(w1)},
        {{f(a1), f(b1), f(a1)}, f(w1)},
        {{f(b1), f(a1), f(a1)}, f(w1)},
        {{f(a2), f(a2), f(b2)}, f(w2)},
        {{f(a2), f(b2), f(a2)}, f(w2)},
        {{f(b2), f(a2), f(a2)}, f(w2)},
    }};
  }();
  return rule;
}

// `normal` is triangle_normal(mesh, triangle), computed once per triangle by the caller.
FootprintSample make_sample(const Mesh& mesh, uint32_t m, uint32_t triangle,
                            const NodeSpaceTriangle& t, vec3 normal, vec2 cell_origin,
                            vec2 local, float area) {
  FootprintSample s;
  s.mesh = m;
  s.triangle = triangle;
  s.barycentric = glm::clamp(barycentric_of(t, cell_origin + local), vec2(0.0f), vec2(1.0f));
  const uvec3 tri = mesh.triangles[triangle];
  const float b0 = 1.0f - s.barycentric.x - s.barycentric.y;
  s.position = b0 * mesh.positions[tri.x] + s.barycentric.x * mesh.positions[tri.y] +
               s.barycentric.y * mesh.positions[tri.z];
  s.normal = normal;
  s.area = area;
  s.in_cell = local;
  return s;
}

}  // namespace

TexelFootprints::TexelFootprints(std::vector<const Mesh*> meshes, int width, int height)
    : meshes_(std::move(meshes)), width_(std::max(0, width)), height_(std::max(0, height)) {
  // Two passes over the triangles' node-space bounding boxes: count, then fill, in (mesh,
  // triangle) order so every cell lists its triangles in one fixed order.
  std::vector<uint32_t> count(cell_count() + 1, 0);
  auto for_each_cell = [&](auto&& visit) {
    for (size_t m = 0; m < meshes_.size(); ++m) {
      const Mesh* mesh = meshes_[m];
      if (!mesh || mesh->lightmap_uvs.size() != mesh->positions.size()) continue;
      for (size_t t = 0; t < mesh->triangles.size(); ++t) {
        NodeSpaceTriangle nst;
        if (!to_node_space(*mesh, uint32_t(t), width_, height_, nst)) continue;
        const vec2 lo = glm::min(nst.q[0], glm::min(nst.q[1], nst.q[2]));
        const vec2 hi = glm::max(nst.q[0], glm::max(nst.q[1], nst.q[2]));
        const int i0 = std::max(0, int(std::floor(lo.x))), j0 = std::max(0, int(std::floor(lo.y)));
        const int i1 = std::min(width_ - 1, int(std::floor(hi.x)));
        const int j1 = std::min(height_ - 1, int(std::floor(hi.y)));
        for (int j = j0; j <= j1; ++j)
          for (int i = i0; i <= i1; ++i) visit(size_t(j) * size_t(width_) + size_t(i), m, t);
      }
    }
  };
  for_each_cell([&](size_t cell, size_t, size_t) { ++count[cell + 1]; });
  for (size_t c = 0; c < cell_count(); ++c) count[c + 1] += count[c];
  cell_start_ = count;
  cell_triangles_.resize(cell_start_.back());
  for_each_cell([&](size_t cell, size_t m, size_t t) {
    cell_triangles_[count[cell]++] = {uint32_t(m), uint32_t(t)};
  });
}

void TexelFootprints::cell_samples(int i, int j, FootprintRule rule, int side, uint64_t seed,
                                   std::vector<FootprintSample>& out) const {
  const size_t cell = size_t(j) * size_t(width_) + size_t(i);
  const vec2 origin{float(i), float(j)};
  if (rule == FootprintRule::quadrature) {
    for (uint32_t k = cell_start_[cell]; k < cell_start_[cell + 1]; ++k) {
      const auto [m, t] = cell_triangles_[k];
      const Mesh& mesh = *meshes_[m];
      NodeSpaceTriangle nst;
      if (!to_node_space(mesh, t, width_, height_, nst)) continue;
      const ClipPolygon poly =
          clip_to_unit_square(nst.q[0] - origin, nst.q[1] - origin, nst.q[2] - origin);
      if (poly.n < 3) continue;
      const vec3 normal = triangle_normal(mesh, t);
      for (int f = 1; f + 1 < poly.n; ++f) {
        const vec2 a = poly.p[0], b = poly.p[f], c = poly.p[f + 1];
        const double piece = fan_piece_area(poly, f);
        if (!(piece > 0.0)) continue;
        for (const QuadraturePoint& qp : radon7()) {
          const vec2 local = qp.b[0] * a + qp.b[1] * b + qp.b[2] * c;
          out.push_back(make_sample(mesh, m, t, nst, normal, origin, local,
                                    float(piece * qp.weight * nst.world_per_cell)));
        }
      }
    }
    return;
  }
  // Stratified: each jittered point belongs to the first listed triangle that holds it.
  if (cell_start_[cell] == cell_start_[cell + 1]) return;
  std::vector<NodeSpaceTriangle> triangles;
  std::vector<uint8_t> usable;
  for (uint32_t k = cell_start_[cell]; k < cell_start_[cell + 1]; ++k) {
    const auto [m, t] = cell_triangles_[k];
    usable.push_back(to_node_space(*meshes_[m], t, width_, height_, triangles.emplace_back()));
  }
  Rng rng(hash_seed(seed, cell, 0x7e7e1));
  const float inv_side = 1.0f / float(side);
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x) {
      const vec2 local = (vec2(float(x), float(y)) + rng.next_2d()) * inv_side;
      for (size_t k = 0; k < triangles.size(); ++k) {
        if (!usable[k]) continue;
        const vec2 b = barycentric_of(triangles[k], origin + local);
        constexpr float eps = -1e-6f;
        if (b.x < eps || b.y < eps || 1.0f - b.x - b.y < eps) continue;
        const auto [m, t] = cell_triangles_[cell_start_[cell] + k];
        out.push_back(make_sample(*meshes_[m], m, t, triangles[k],
                                  triangle_normal(*meshes_[m], t), origin, local,
                                  float(triangles[k].world_per_cell) * inv_side * inv_side));
        break;
      }
    }
}

double TexelFootprints::cell_coverage(int i, int j,
                                      const std::vector<std::vector<uint8_t>>* hidden) const {
  const size_t cell = size_t(j) * size_t(width_) + size_t(i);
  const vec2 origin{float(i), float(j)};
  double covered = 0.0;
  for (uint32_t k = cell_start_[cell]; k < cell_start_[cell + 1]; ++k) {
    const auto [m, t] = cell_triangles_[k];
    if (hidden && m < hidden->size() && t < (*hidden)[m].size() && (*hidden)[m][t]) continue;
    NodeSpaceTriangle nst;
    if (!to_node_space(*meshes_[m], t, width_, height_, nst)) continue;
    const ClipPolygon poly =
        clip_to_unit_square(nst.q[0] - origin, nst.q[1] - origin, nst.q[2] - origin);
    for (int f = 1; f + 1 < poly.n; ++f) covered += fan_piece_area(poly, f);
  }
  return std::min(1.0, covered);
}

std::vector<double> texel_row_work(const TexelFootprints& footprints,
                                   const std::vector<std::vector<uint8_t>>* hidden) {
  std::vector<double> work(size_t(footprints.height()), 0.0);
  for (int j = 0; j < footprints.height(); ++j)
    for (int i = 0; i < footprints.width(); ++i)
      if (!footprints.cell_empty(size_t(j) * size_t(footprints.width()) + size_t(i)))
        work[size_t(j)] += footprints.cell_coverage(i, j, hidden);
  return work;
}

std::vector<TexelRows> partition_texel_rows(std::span<const double> row_work, int count) {
  const int rows = int(row_work.size());
  count = std::max(1, count);
  std::vector<double> prefix(row_work.size() + 1, 0.0);  // prefix[r]: work of rows 0 .. r - 1
  for (size_t r = 0; r < row_work.size(); ++r) prefix[r + 1] = prefix[r] + row_work[r];
  const double total = prefix.back();
  std::vector<TexelRows> ranges(static_cast<size_t>(count));
  int begin = 0;
  for (int k = 0; k < count; ++k) {
    int end = rows;
    if (k + 1 < count && !(total > 0.0)) {
      end = int(int64_t(rows) * (k + 1) / count);
    } else if (k + 1 < count) {
      const double target = total * double(k + 1) / double(count);
      // The first row at or past the target, or the one before it if nearer.
      end = int(std::lower_bound(prefix.begin() + begin, prefix.end(), target) - prefix.begin());
      if (end > begin && target - prefix[size_t(end - 1)] <= prefix[size_t(end)] - target) --end;
    }
    ranges[size_t(k)] = {begin, end};
    begin = end;
  }
  return ranges;
}

namespace {

// What the points of one cell give one of its corner nodes: the tent-weighted moments of the
// points' positions (x, y relative to the node, in texels) and, per layer, of the light there.
struct Moments {
  double w = 0, wx = 0, wy = 0, wxx = 0, wxy = 0, wyy = 0;
  void add(double weight, double x, double y) {
    w += weight, wx += weight * x, wy += weight * y;
    wxx += weight * x * x, wxy += weight * x * y, wyy += weight * y * y;
  }
  void add(const Moments& o) {
    w += o.w, wx += o.wx, wy += o.wy, wxx += o.wxx, wxy += o.wxy, wyy += o.wyy;
  }
};
// Per layer, the tent-weighted moments of the light: f, then (plane fit only) f x and f y, as
// consecutive dvec3s; without the plane fit only f is kept (a third of the work and memory,
// which light groups multiply by their count).
void add_value_moments(glm::dvec3* out, size_t components, double weight, double x, double y,
                       glm::dvec3 value) {
  out[0] += weight * value;
  if (components == 3) out[1] += weight * x * value, out[2] += weight * y * value;
}

// The plane fit's normal-equation inverse at a node, once for all layers; nullopt: the node
// takes the mean. The weighted least-squares plane through its points, at the node: where the
// footprint is whole (symmetric about the node) this is exactly the tent-weighted mean; where a
// chart border cuts it, the plane extrapolates to the node, so bilinear filtering reproduces a
// linear field up to the border and the two sides of a chart seam agree. Thin footprints (the
// plane is ill-posed) keep the mean.
std::optional<glm::dmat3> plane_inverse(const Moments& m, bool plane_fit) {
  if (!plane_fit || !(m.w > 0.0)) return std::nullopt;
  const glm::dmat3 a(m.w, m.wx, m.wy, m.wx, m.wxx, m.wxy, m.wy, m.wxy, m.wyy);
  const double det = glm::determinant(a);
  // A whole footprint has det = w^3 / 36 x ~1 (tent variance 1/6 per axis): 1e-3 of that is a
  // sliver of under a texel's tenth.
  if (!(det > 1e-3 * m.w * m.w * m.w / 36.0)) return std::nullopt;
  return glm::inverse(a);
}

// The node's value from one layer's moments `v` (add_value_moments' layout).
// `signed_values`: the mean as it is (FillTexelsParams::signed_values).
vec3 node_value(const Moments& m, const glm::dvec3* v, const std::optional<glm::dmat3>& inverse,
                bool signed_values) {
  if (!(m.w > 0.0)) return vec3(0.0f);
  if (signed_values) return vec3(v[0] / m.w);
  if (!inverse) return vec3(glm::max(v[0] / m.w, glm::dvec3(0.0)));
  glm::dvec3 value;
  for (int c = 0; c < 3; ++c) value[c] = (*inverse * glm::dvec3(v[0][c], v[1][c], v[2][c])).x;
  return vec3(glm::max(value, glm::dvec3(0.0)));  // light is never negative
}

}  // namespace

size_t TexelFootprints::touched_cells() const {
  size_t count = 0;
  for (size_t cell = 0; cell < cell_count(); ++cell) count += cell_empty(cell) ? 0 : 1;
  return count;
}

FillTexelsParams noisy_fill(int side, uint64_t seed, const char* stage,
                            const std::vector<std::vector<uint8_t>>& hidden) {
  FillTexelsParams fill;
  fill.rule = FootprintRule::stratified;
  fill.side = side;
  fill.seed = seed;
  fill.stage = stage;
  fill.plane_fit_at_borders = false;
  fill.hidden_triangles = &hidden;
  return fill;
}

int side_for_budget(double points, size_t cells, int lo, int hi) {
  const double side = std::floor(std::sqrt(points / double(std::max<size_t>(cells, 1))));
  return int(std::clamp(side, double(lo), double(hi)));
}

void drop_hidden_samples(std::vector<FootprintSample>& samples,
                         const std::vector<std::vector<uint8_t>>* hidden) {
  if (!hidden) return;
  std::erase_if(samples, [hidden](const FootprintSample& p) {
    return p.mesh < hidden->size() && p.triangle < (*hidden)[p.mesh].size() &&
           (*hidden)[p.mesh][p.triangle] != 0;
  });
}

std::vector<vec3> fill_texels(const TexelFootprints& footprints, const TexelEstimator& estimate,
                              const FillTexelsParams& params, const Progress& progress,
                              std::vector<double>* weight_out) {
  return std::move(fill_texel_layers(footprints, 1, estimate, params, progress, weight_out)[0]);
}

namespace {
// A cell estimator as a row estimator: each cell's points on their own, left to right.
TexelRowEstimator cell_by_cell(const TexelEstimator& estimate) {
  return [&estimate](std::span<const FootprintSample> samples, std::span<const size_t> first,
                     std::span<const size_t> cells, std::span<vec3> values) {
    const size_t layers = samples.empty() ? 1 : values.size() / samples.size();
    for (size_t c = 0; c < cells.size(); ++c) {
      const size_t n = first[c + 1] - first[c];
      estimate(samples.subspan(first[c], n), values.subspan(layers * first[c], layers * n),
               cells[c]);
    }
  };
}
}  // namespace

std::vector<std::vector<vec3>> fill_texel_layers(const TexelFootprints& footprints, size_t layers,
                                                 const TexelEstimator& estimate,
                                                 const FillTexelsParams& params,
                                                 const Progress& progress,
                                                 std::vector<double>* weight_out) {
  return fill_texel_layers(footprints, layers, cell_by_cell(estimate), params, progress,
                           weight_out);
}

void fill_texel_layers_into(const TexelFootprints& footprints, size_t layers,
                            const TexelEstimator& estimate, const FillTexelsParams& params,
                            const TexelSink& sink, const Progress& progress) {
  fill_texel_layers_into(footprints, layers, cell_by_cell(estimate), params, sink, progress);
}

std::vector<std::vector<vec3>> fill_texel_layers(const TexelFootprints& footprints, size_t layers,
                                                 const TexelRowEstimator& estimate,
                                                 const FillTexelsParams& params,
                                                 const Progress& progress,
                                                 std::vector<double>* weight_out) {
  layers = std::max<size_t>(layers, 1);
  const size_t nodes = footprints.cell_count();
  std::vector<std::vector<vec3>> values(layers, std::vector<vec3>(nodes, vec3(0.0f)));
  if (weight_out) weight_out->assign(nodes, 0.0);
  fill_texel_layers_into(
      footprints, layers, estimate, params,
      [&](size_t node, std::span<const vec3> node_values, double weight) {
        for (size_t l = 0; l < layers; ++l) values[l][node] = node_values[l];
        if (weight_out) (*weight_out)[node] = weight;
      },
      progress);
  return values;
}

namespace {
// One cell row's points, their cells and their estimates (fill_texel_layers_into).
struct RowScratch {
  std::vector<FootprintSample> samples, cell_points;
  std::vector<size_t> first, cells, columns;
  std::vector<vec3> estimates;
};
}  // namespace

void fill_texel_layers_into(const TexelFootprints& footprints, size_t layers,
                            const TexelRowEstimator& estimate, const FillTexelsParams& params,
                            const TexelSink& sink, const Progress& progress) {
  const int width = footprints.width(), height = footprints.height();
  const int side = std::max(1, params.side);
  layers = std::max<size_t>(layers, 1);
  // Cell rows go in bands (memory: a band, not the atlas); the rows of a band run in parallel,
  // then each node of the band's node rows sums its four cells in one fixed order: the same
  // bits whatever the thread count. Cell row j lies between node rows j and j + 1. Per cell,
  // 4 corners' Moments and 4 x layers value moments (corner-major, `components` dvec3s each).
  // A band's moments cost what one layer's with the plane fit do: light groups' many layers
  // take fewer rows a band (the bits do not depend on it).
  if (params.signed_values && params.plane_fit_at_borders)
    throw std::invalid_argument("fill_texels: signed values take no plane fit");
  const size_t components = params.plane_fit_at_borders ? 3 : 1;
  const int band_rows = int(
      std::clamp<size_t>(size_t(kTexelBandRows) * 3 / (layers * components), 4, kTexelBandRows));
  const TexelRows all{0, height};
  const TexelRows rows_to_fill = params.rows.value_or(all);
  if (rows_to_fill.begin < 0 || rows_to_fill.end > height || rows_to_fill.count() < 0)
    throw std::invalid_argument("fill_texels: node rows " + std::to_string(rows_to_fill.begin) +
                                ".." + std::to_string(rows_to_fill.end) + " outside 0.." +
                                std::to_string(height));
  const size_t per_layer = components, per_corner = layers * components, per_cell = 4 * per_corner;
  std::vector<std::array<Moments, 4>> previous(static_cast<size_t>(width));  // cell row above
  std::vector<glm::dvec3> previous_values(size_t(width) * per_cell);
  std::vector<std::array<Moments, 4>> band;
  std::vector<glm::dvec3> band_values;
  const int rows_to_do = rows_to_fill.count();
  std::atomic<int> rows_done{0};
  std::mutex report;
  // Cell row j's moments into `row` and `row_values` (width cells).
  auto fill_cell_row = [&](int j, std::array<Moments, 4>* row, glm::dvec3* row_values) {
    // The row's points, cell after cell, estimated at once. The buffers are the thread's,
    // kept from row to row: a row's quadrature points (~0.4 MB) in fresh vectors were mapped
    // and zeroed by the kernel again each row (a quarter of a room bake's page faults).
    thread_local RowScratch scratch;
    auto& [samples, cell_points, first, cells, columns, estimates] = scratch;
    samples.clear(), cells.clear(), columns.clear();
    first.assign(1, 0);
    for (int i = 0; i < width; ++i) {
      const size_t cell = size_t(j) * size_t(width) + size_t(i);
      if (footprints.cell_empty(cell)) continue;
      cell_points.clear();
      footprints.cell_samples(i, j, params.rule, side, params.seed, cell_points);
      drop_hidden_samples(cell_points, params.hidden_triangles);
      if (cell_points.empty()) continue;
      samples.insert(samples.end(), cell_points.begin(), cell_points.end());
      first.push_back(samples.size());
      cells.push_back(cell);
      columns.push_back(size_t(i));
    }
    if (cells.empty()) return;
    estimates.assign(samples.size() * layers, vec3(0.0f));
    // Isolated: an estimator that waits on tasks of its own must not run another row on this
    // thread meanwhile (it would take these buffers).
    tbb::this_task_arena::isolate([&] { estimate(samples, first, cells, estimates); });
    for (size_t c = 0; c < cells.size(); ++c) {
      const size_t n = first[c + 1] - first[c];
      const FootprintSample* points = &samples[first[c]];
      const vec3* cell_estimates = &estimates[layers * first[c]];
      std::array<Moments, 4>& out = row[columns[c]];
      glm::dvec3* out_values = row_values + columns[c] * per_cell;
      for (size_t s = 0; s < n; ++s) {
        const double x = points[s].in_cell.x, y = points[s].in_cell.y;
        const double tent[4] = {(1 - x) * (1 - y), x * (1 - y), (1 - x) * y, x * y};
        const double corner_x[4] = {0, 1, 0, 1}, corner_y[4] = {0, 0, 1, 1};
        for (int k = 0; k < 4; ++k) {
          const double w = tent[k] * double(points[s].area);
          out[size_t(k)].add(w, x - corner_x[k], y - corner_y[k]);
          for (size_t l = 0; l < layers; ++l)
            add_value_moments(out_values + size_t(k) * per_corner + l * per_layer, components, w,
                              x - corner_x[k], y - corner_y[k],
                              glm::dvec3(cell_estimates[l * n + s]));
        }
      }
    }
  };
  for (int band_start = rows_to_fill.begin; band_start < rows_to_fill.end;
       band_start += band_rows) {
    const int rows = std::min(band_rows, rows_to_fill.end - band_start);
    // Another shard fills the rows above: their last cell row again, the same bits.
    if (band_start == rows_to_fill.begin && band_start > 0)
      fill_cell_row(band_start - 1, previous.data(), previous_values.data());
    band.assign(size_t(rows) * size_t(width), {});
    band_values.assign(size_t(rows) * size_t(width) * per_cell, glm::dvec3(0.0));
    std::atomic<bool> stopped{false};
    tbb::parallel_for(0, rows, [&](int r) {
      if (stopped || progress.cancelled()) {
        stopped = true;
        return;
      }
      fill_cell_row(band_start + r, &band[size_t(r) * size_t(width)],
                    &band_values[size_t(r) * size_t(width) * per_cell]);
      const int done = ++rows_done;
      std::lock_guard lock(report);
      progress.update(params.stage, double(done) / double(std::max(1, rows_to_do)));
    });
    progress.throw_if_cancelled();
    // Node rows band_start .. band_start + rows - 1: cells of rows j - 1 (above) and j.
    tbb::parallel_for(0, rows, [&](int r) {
      const int j = band_start + r;
      std::vector<glm::dvec3> v(per_corner);
      std::vector<vec3> node_values(layers);
      for (int i = 0; i < width; ++i) {
        Moments m;
        std::fill(v.begin(), v.end(), glm::dvec3(0.0));
        // The cell's moments and its values' (null outside the atlas).
        auto cell = [&](int ci, int row) -> std::pair<const std::array<Moments, 4>*,
                                                      const glm::dvec3*> {
          if (ci < 0 || ci >= width || row < 0) return {nullptr, nullptr};
          if (row < band_start)
            return {&previous[size_t(ci)], &previous_values[size_t(ci) * per_cell]};
          const size_t index = size_t(row - band_start) * size_t(width) + size_t(ci);
          return {&band[index], &band_values[index * per_cell]};
        };
        // Cell (i-1, j-1) has this node as its corner 3 (x = 1, y = 1), and so on.
        const int ci[4] = {i - 1, i, i - 1, i}, cj[4] = {j - 1, j - 1, j, j},
                  corner[4] = {3, 2, 1, 0};
        for (int k = 0; k < 4; ++k)
          if (const auto [c, cv] = cell(ci[k], cj[k]); c) {
            m.add((*c)[size_t(corner[k])]);
            const glm::dvec3* from = cv + size_t(corner[k]) * per_corner;
            for (size_t e = 0; e < per_corner; ++e) v[e] += from[e];
          }
        const size_t node = size_t(j) * size_t(width) + size_t(i);
        const std::optional<glm::dmat3> inverse = plane_inverse(m, params.plane_fit_at_borders);
        for (size_t l = 0; l < layers; ++l)
          node_values[l] = node_value(m, &v[l * per_layer], inverse, params.signed_values);
        sink(node, node_values, m.w);
      }
    });
    std::copy_n(band.begin() + std::ptrdiff_t(size_t(rows - 1) * size_t(width)), size_t(width),
                previous.begin());
    std::copy_n(band_values.begin() + std::ptrdiff_t(size_t(rows - 1) * size_t(width) * per_cell),
                size_t(width) * per_cell, previous_values.begin());
  }
}

void dilate_texels(int width, int height, const std::vector<uint8_t>& filled,
                   std::vector<vec3>& values, int rings) {
  fill_from_neighbours(width, height, filled, std::vector<uint8_t>(filled.size(), 1), values,
                       rings);
}

void fill_from_neighbours(int width, int height, const std::vector<uint8_t>& filled_in,
                          const std::vector<uint8_t>& fillable, std::vector<vec3>& values,
                          int rings) {
  std::vector<uint8_t> filled = filled_in;
  std::vector<std::pair<size_t, vec3>> updates;
  for (int ring = 0; ring < rings; ++ring) {
    updates.clear();
    for (int j = 0; j < height; ++j)
      for (int i = 0; i < width; ++i) {
        const size_t index = size_t(j) * size_t(width) + size_t(i);
        if (filled[index] || !fillable[index]) continue;
        vec3 sum(0.0f);
        int count = 0;
        for (int dj = -1; dj <= 1; ++dj)
          for (int di = -1; di <= 1; ++di) {
            const int x = i + di, y = j + dj;
            if (x < 0 || y < 0 || x >= width || y >= height) continue;
            const size_t n = size_t(y) * size_t(width) + size_t(x);
            if (!filled[n]) continue;
            sum += values[n];
            ++count;
          }
        if (count > 0) updates.emplace_back(index, sum / float(count));
      }
    if (updates.empty()) break;
    for (const auto& [index, value] : updates) {
      values[index] = value;
      filled[index] = 1;
    }
  }
}

std::vector<std::vector<uint8_t>> hidden_surface_triangles(const std::vector<const Mesh*>& surfaces,
                                                           const Accel& accel,
                                                           bool sheltered_hidden) {
  std::vector<std::vector<uint8_t>> hidden(surfaces.size());
  const std::vector<uint8_t> closed = closed_meshes(accel.scene());
  tbb::parallel_for(size_t(0), surfaces.size(), [&](size_t m) {
    if (!surfaces[m]) return;
    hidden[m] = covered_triangles(*surfaces[m], accel, closed);
    for (uint8_t& h : hidden[m]) h = h == kCovered || (sheltered_hidden && h == kSheltered);
  });
  return hidden;
}

}  // namespace lb
