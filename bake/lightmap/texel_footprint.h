#pragma once
// The surface under each lightmap texel, as sample points any estimator can fill.
//
// A lightmap is read with bilinear filtering, so texel node (i, j) stands for the surface under
// the four cells around it, weighted by its bilinear "tent" (atlas.h). Its stored value is the
// tent-weighted mean of the light over that footprint,
//     value(node) = sum_s w_node(s) f(s) / sum_s w_node(s),   w_node(s) = tent(s) * area(s),
// which keeps energy: sum over nodes of value x texel area x pi = the integral of pi f over the
// surface, because the tents of the four corners of a cell sum to 1 everywhere. Where a chart
// border cuts a node's footprint, the mean would belong to a point inside the chart, not to
// the node, and the two sides of a seam would disagree by most of a texel's change of the
// light; there the node takes the weighted least-squares plane through its points, evaluated
// at the node (the same as the mean for a whole footprint), so bilinear filtering reproduces a
// linear field right up to the border (tests/lightmap: seam 1e-6, power moved by 1e-5); a
// noisy estimator keeps the mean there (FillTexelsParams::plane_fit_at_borders).
//
// Work goes by cell (the square between four nodes): each cell's surface points are made once,
// the estimator fills them, and each point feeds the four nodes around it. Cells run in
// parallel; each node then sums its four cells in a fixed order, so the bits do not depend on
// the thread count. Two point rules:
//   quadrature  each triangle is clipped to the cell and the pieces integrated with Radon's
//               7-point rule (exact to degree 5): exact for a field linear over each triangle
//               times the tent (degree 3), e.g. vertex radiosity;
//   stratified  side x side jittered points per cell (deterministic per cell and seed), each
//               standing for the part of the cell's area it falls in: the supersampling for
//               estimators with visibility (direct light, final gather).
// Shards (issue 16, `lightbake export --shard i/n`): shard i fills one contiguous range of node
// rows (partition_texel_rows), chosen from the rows' work (texel_row_work: their surface, hence
// their stratified points) so that each holds about 1/n of it, and computes the one cell row
// above its range again, as the shard before it does: every node it fills has the bits of the
// whole run, since a cell's points and estimates depend only on the cell and the seed. Within a
// range, rows still go in bands of at most kTexelBandRows (memory).
// Used by the soft light (soft_light.h) and the direct light (direct_texels.h) of the export's
// lightmap; another estimator fills texels the same way through fill_texels.

#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <vector>

#include "bake/progress.h"
#include "bake/scene.h"

namespace lb {

// One surface point under a cell.
struct FootprintSample {
  uint32_t mesh = 0;       // scene mesh index
  uint32_t triangle = 0;   // triangle of the footprint mesh (TexelFootprints::mesh(mesh))
  vec2 barycentric{0.0f};  // (b1, b2) of that triangle, as in Hit
  vec3 position{0.0f};     // world, m
  vec3 normal{0.0f};       // the triangle's geometric normal (unit, its front side)
  float area = 0.0f;       // m^2 of surface the point stands for (before the tents)
  vec2 in_cell{0.0f};      // position in the cell, [0,1]^2 (x right, y up in node space)
};

enum class FootprintRule { quadrature, stratified };

// Node rows [begin, end).
struct TexelRows {
  int begin = 0;
  int end = 0;
  int count() const { return end - begin; }
  bool operator==(const TexelRows&) const = default;
};

class TexelFootprints {
 public:
  // meshes[m]: the surface of scene mesh m with lightmap UVs into a width x height atlas, or
  // null (no map). The meshes must outlive this object.
  TexelFootprints(std::vector<const Mesh*> meshes, int width, int height);

  int width() const { return width_; }
  int height() const { return height_; }
  const Mesh* mesh(size_t m) const { return meshes_[m]; }
  size_t cell_count() const { return size_t(width_) * size_t(height_); }
  bool cell_empty(size_t cell) const { return cell_start_[cell] == cell_start_[cell + 1]; }
  // Cells some triangle's UV bounding box touches (the cells fill_texels visits).
  size_t touched_cells() const;

  // The points of cell (i, j) (between nodes i..i+1, j..j+1), appended to `out`. `seed` and
  // `side` only matter for the stratified rule.
  void cell_samples(int i, int j, FootprintRule rule, int side, uint64_t seed,
                    std::vector<FootprintSample>& out) const;
  // The share of cell (i, j) that surface covers, in [0, 1] (its triangles clipped to the cell;
  // overlaps counted once at most by the cap): the stratified rule's share of points there.
  // `hidden` (FillTexelsParams::hidden_triangles): those triangles do not count.
  double cell_coverage(int i, int j,
                       const std::vector<std::vector<uint8_t>>* hidden = nullptr) const;

 private:
  std::vector<const Mesh*> meshes_;
  int width_ = 0, height_ = 0;
  // Triangles whose UV bounding box touches each cell (compressed rows).
  std::vector<uint32_t> cell_start_;
  std::vector<std::pair<uint32_t, uint32_t>> cell_triangles_;  // (mesh, triangle)
};

// Fills `values` (one per sample) with the estimate of the light there, W/(sr m^2) (E/pi).
// Called from several threads at once, each time with the points of one cell (`cell` = j *
// width + i, for per-cell random streams: the same bits whatever the thread count).
using TexelEstimator = std::function<void(std::span<const FootprintSample> samples,
                                          std::span<vec3> values, size_t cell)>;

// The same for a cell row's points at once (an estimator that traces them together, in waves):
// non-empty cell c (left to right) has points samples[first[c] .. first[c + 1]), index
// cells[c], and its values at values[L * first[c] ..] for L layers, laid out as
// TexelEstimator's (values[L * first[c] + l * n_c + s]).
using TexelRowEstimator = std::function<void(
    std::span<const FootprintSample> samples, std::span<const size_t> first,
    std::span<const size_t> cells, std::span<vec3> values)>;

struct FillTexelsParams {
  FootprintRule rule = FootprintRule::quadrature;
  int side = 4;       // stratified: side x side points per cell (16 a cell, 64 a node)
  uint64_t seed = 1;  // stratified: jitter seed
  const char* stage = "lightmap texels";  // progress stage name
  // Border nodes (footprint cut by a chart border) take the least-squares plane at the node
  // (no seam for a smooth field) instead of the mean. For exact, smooth estimates (quadrature
  // of vertex radiosity); a noisy estimator's plane extrapolates its noise (measured on the
  // direct light at 64 rays a texel: 51% rms at border texels against 3.1% inside), so it
  // keeps the mean, whose seam is bounded by the light's change over a texel.
  bool plane_fit_at_borders = true;
  // Values may be negative (a difference of two estimates, e.g. the soft light's gather less
  // the interpolation at the same points): the mean is kept as it is, where light (the default)
  // is never below 0. Only without the plane fit.
  bool signed_values = false;
  // Fill only these node rows (a shard's, partition_texel_rows); the others stay 0.
  std::optional<TexelRows> rows;
  // Per scene mesh, 1 for each triangle of its footprint surface that lies inside other
  // geometry (hidden_surface_triangles): its points are dropped before the estimator sees them,
  // so a node at a contact holds the light of the surface one can see, not a mean with the dark
  // under a block (issue 36). Null or a mesh's empty list: every point counts.
  const std::vector<std::vector<uint8_t>>* hidden_triangles = nullptr;
};

// The fill of a ray-traced estimator (bake_lightmap's direct term, the directional maps'):
// stratified side x side points a cell from `seed`, the mean at borders (no plane fit), points
// on triangles `hidden` flags dropped (hidden_surface_triangles; must outlive the fill).
FillTexelsParams noisy_fill(int side, uint64_t seed, const char* stage,
                            const std::vector<std::vector<uint8_t>>& hidden);

// Points per cell side for a budget of `points` over `cells` cells, within [lo, hi]: the largest
// side with side^2 x cells <= points. Few texels (game densities) take more points each, so a
// texel 10 cm wide is sampled about as finely as one of 2 cm, at a bounded cost.
int side_for_budget(double points, size_t cells, int lo, int hi);

// Removes the points on triangles `hidden` flags (FillTexelsParams::hidden_triangles; null: none).
void drop_hidden_samples(std::vector<FootprintSample>& samples,
                         const std::vector<std::vector<uint8_t>>* hidden);

inline constexpr int kTexelBandRows = 32;  // node rows per band (memory: a band's cells)

// The work of each node row j when sharding: the surface in cell row j (between node rows j and
// j + 1, which the shard holding node row j computes), in cells (a covered cell is 1). The
// stratified rule makes a cell's points in proportion to its surface and each costs one
// estimate (the direct light's shadow ray), most of a cell's time: on cornell_glass at 16 x 16
// a cell, the time of a cell row follows its points within 9% rms. Depends on the UVs alone.
// Surface hidden under other geometry (`hidden`, as FillTexelsParams::hidden_triangles) takes
// no estimate, so it is no work.
std::vector<double> texel_row_work(const TexelFootprints& footprints,
                                   const std::vector<std::vector<uint8_t>>* hidden = nullptr);

// `count` contiguous ranges of node rows, in shard order, covering [0, row_work.size()) without
// overlap (some empty when count exceeds the rows): boundary k is the row whose prefix of work
// is nearest k / count of the total (the lower row on a tie), so each range's work is within
// the largest row's of 1/count of the total. Without work, rows are split by count. Depends on
// `row_work` alone, so every shard computes the same ranges.
std::vector<TexelRows> partition_texel_rows(std::span<const double> row_work, int count);

// value(node) as in the header comment, width*height, 0 where no surface lies under a node;
// `weight` (optional) receives sum_s w_node(s), m^2 (the node's texel area for quadrature).
// Throws Cancelled when `progress` is cancelled.
std::vector<vec3> fill_texels(const TexelFootprints& footprints, const TexelEstimator& estimate,
                              const FillTexelsParams& params, const Progress& progress = {},
                              std::vector<double>* weight = nullptr);

// `layers` maps at once from the same points, rule and weights, at the cost of one pass over
// the points: `estimate` fills layers x samples values, layer-major (values[l * samples + s]).
// Layer l is what fill_texels gives with layer l's estimates (light groups: each group's map).
std::vector<std::vector<vec3>> fill_texel_layers(const TexelFootprints& footprints, size_t layers,
                                                 const TexelEstimator& estimate,
                                                 const FillTexelsParams& params,
                                                 const Progress& progress = {},
                                                 std::vector<double>* weight = nullptr);

// The same with a row estimator: the values fill_texel_layers gives when each cell's estimates
// are the row estimator's.
std::vector<std::vector<vec3>> fill_texel_layers(const TexelFootprints& footprints, size_t layers,
                                                 const TexelRowEstimator& estimate,
                                                 const FillTexelsParams& params,
                                                 const Progress& progress = {},
                                                 std::vector<double>* weight = nullptr);

// Receives node `node`'s `layers` values (fill_texel_layers' values[l][node]) and its weight
// (sum_s w_node(s), 0 where no surface lies under it), once per node of the rows filled, from
// several threads at once.
using TexelSink = std::function<void(size_t node, std::span<const vec3> values, double weight)>;

// fill_texel_layers handing each node to `sink` as its band of rows is done, in place of
// returning the maps (memory: a caller that folds the values into maps of its own holds no
// layers of these); the same values, bit for bit.
void fill_texel_layers_into(const TexelFootprints& footprints, size_t layers,
                            const TexelEstimator& estimate, const FillTexelsParams& params,
                            const TexelSink& sink, const Progress& progress = {});

void fill_texel_layers_into(const TexelFootprints& footprints, size_t layers,
                            const TexelRowEstimator& estimate, const FillTexelsParams& params,
                            const TexelSink& sink, const Progress& progress = {});

// Fills nodes with no surface next to filled ones with the mean of their filled neighbours,
// `rings` times (so filtering and mipmaps never pull in black at chart borders).
void dilate_texels(int width, int height, const std::vector<uint8_t>& filled,
                   std::vector<vec3>& values, int rings);

// The same, for the nodes with `fillable` set only (the others keep their values and are never
// read unless filled): e.g. nodes whose whole footprint is hidden under other geometry take the
// mean of the visible nodes around them, ring by ring, at most `rings` rings deep.
void fill_from_neighbours(int width, int height, const std::vector<uint8_t>& filled,
                          const std::vector<uint8_t>& fillable, std::vector<vec3>& values,
                          int rings);

// Per footprint surface (null: an empty list), 1 for each triangle inside other geometry: the
// coverage probes of radiosity's contact cuts (bake/contact_cuts.h). The refined
// radiosity meshes are cut along contacts, so their triangles lie wholly on one side.
// `sheltered_hidden`: surface under an open sheet (kSheltered) counts as hidden too.
class Accel;
std::vector<std::vector<uint8_t>> hidden_surface_triangles(const std::vector<const Mesh*>& surfaces,
                                                           const Accel& accel,
                                                           bool sheltered_hidden = false);

}  // namespace lb
