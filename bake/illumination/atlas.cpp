#include "bake/illumination/atlas.h"

#include <tbb/parallel_for.h>

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <numeric>
#include <stdexcept>
#include <string>

#include "bake/clip_polygon.h"
#include "bake/illumination/atlas_unfold.h"
#include "bake/illumination/given_uvs.h"
#include "bake/sampling.h"

namespace lb {

namespace {

using OmMesh = OpenMesh::TriMesh_ArrayKernelT<>;

// A chart while it is being built: triangles of one mesh and the planar coordinates (metres)
// of their vertices.
struct ChartBuild {
  int mesh = -1;
  std::vector<uint32_t> triangles;
  std::vector<uint32_t> vertices;
  vec2 lo{1e30f}, hi{-1e30f};
  float texel_size = 0.0f;
  bool given_uvs = false;
  glm::ivec2 size{0}, offset{0};
  bool upright = false;  // packed turned a quarter: its rectangle is size.y x size.x
  glm::ivec2 placed() const { return upright ? glm::ivec2(size.y, size.x) : size; }
};

// ---- charts of one mesh -------------------------------------------------------------------

// Edge adjacency through OpenMesh, with vertices welded by position: meshes split at hard
// edges or UV seams (flat-shaded exports) still grow charts across their split vertices, which
// is fine because split copies at one position get the same projected UV. Faces OpenMesh
// refuses (non-manifold) get no neighbours and become charts of their own.
std::vector<std::vector<uint32_t>> face_neighbours(const Mesh& mesh) {
  OmMesh om;
  std::map<std::array<float, 3>, OmMesh::VertexHandle> welded;
  std::vector<OmMesh::VertexHandle> vh(mesh.positions.size());
  for (size_t v = 0; v < mesh.positions.size(); ++v) {
    const vec3 p = mesh.positions[v];
    const auto [it, inserted] = welded.try_emplace({p.x, p.y, p.z});
    if (inserted) it->second = om.add_vertex(OmMesh::Point(p.x, p.y, p.z));
    vh[v] = it->second;
  }
  std::vector<int> face_of_om;  // OpenMesh face index -> triangle
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const uvec3 tri = mesh.triangles[t];
    if (vh[tri.x] == vh[tri.y] || vh[tri.y] == vh[tri.z] || vh[tri.x] == vh[tri.z]) continue;
    const auto fh = om.add_face(vh[tri.x], vh[tri.y], vh[tri.z]);
    if (fh.is_valid()) {
      if (size_t(fh.idx()) >= face_of_om.size()) face_of_om.resize(size_t(fh.idx()) + 1, -1);
      face_of_om[size_t(fh.idx())] = int(t);
    }
  }
  std::vector<std::vector<uint32_t>> neighbours(mesh.triangles.size());
  for (const auto fh : om.faces()) {
    const int t = face_of_om[size_t(fh.idx())];
    for (const auto nb : om.ff_range(fh))
      neighbours[size_t(t)].push_back(uint32_t(face_of_om[size_t(nb.idx())]));
  }
  return neighbours;
}

vec3 area_weighted_normal(const Mesh& mesh, const std::vector<uint32_t>& triangles) {
  glm::dvec3 n(0.0);
  for (uint32_t t : triangles)
    n += double(triangle_area(mesh, t)) * glm::dvec3(triangle_normal(mesh, t));
  const double length = glm::length(n);
  return length > 0.0 ? vec3(n / length) : vec3(0.0f, 0.0f, 1.0f);
}

void collect_vertices(const Mesh& mesh, ChartBuild& chart) {
  std::vector<uint32_t>& v = chart.vertices;
  for (uint32_t t : chart.triangles)
    for (int k = 0; k < 3; ++k) v.push_back(mesh.triangles[t][k]);
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
}

// Grows charts over edge-adjacent faces whose normals stay close to the seed's. Returns the
// chart of each triangle (-1 for degenerate ones) and the chart count.
int grow_charts(const Mesh& mesh, const std::vector<std::vector<uint32_t>>& neighbours,
                float cos_limit, std::vector<int>& chart_of) {
  const size_t nt = mesh.triangles.size();
  chart_of.assign(nt, -1);
  int chart_count = 0;
  std::vector<uint32_t> stack;
  for (size_t seed = 0; seed < nt; ++seed) {
    if (chart_of[seed] >= 0 || !(triangle_area(mesh, seed) > 0.0f)) continue;
    const vec3 seed_normal = triangle_normal(mesh, seed);
    const int id = chart_count++;
    chart_of[seed] = id;
    stack.assign(1, uint32_t(seed));
    while (!stack.empty()) {
      const uint32_t t = stack.back();
      stack.pop_back();
      for (uint32_t nb : neighbours[t]) {
        if (chart_of[nb] >= 0 || !(triangle_area(mesh, nb) > 0.0f)) continue;
        if (glm::dot(triangle_normal(mesh, nb), seed_normal) < cos_limit) continue;
        chart_of[nb] = id;
        stack.push_back(nb);
      }
    }
  }
  return chart_count;
}

// Lightmap UVs are per vertex, so a vertex used by two charts is split: the first chart (in
// triangle order) keeps it, every other chart gets its own copy. In an unfolded chart a vertex
// can also have two places (where a strip closes around a cylinder): corners within `tolerance`
// of each other share a copy, others get their own. Empty if nothing is shared.
VertexSplit split_shared_vertices(const Mesh& mesh, const std::vector<int>& chart_of,
                                  const std::vector<uint8_t>& unfolded,
                                  const std::vector<std::array<vec2, 3>>& corners,
                                  float tolerance) {
  VertexSplit split;
  split.triangles = mesh.triangles;
  std::vector<int> owner(mesh.positions.size(), -1);
  std::vector<vec2> owner_place(mesh.positions.size(), vec2(0.0f));
  // (vertex, chart) -> its copies and their places
  std::map<std::pair<uint32_t, int>, std::vector<std::pair<vec2, uint32_t>>> copies;
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const int chart = chart_of[t];
    if (chart < 0) continue;
    const bool placed = unfolded[size_t(chart)] != 0;
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = mesh.triangles[t][k];
      const vec2 place = placed ? corners[t][size_t(k)] : vec2(0.0f);
      if (owner[v] < 0) owner[v] = chart, owner_place[v] = place;
      if (owner[v] == chart && glm::distance(owner_place[v], place) <= tolerance) continue;
      auto& list = copies[{v, chart}];
      uint32_t index = 0;
      bool found = false;
      for (const auto& [p, copy] : list)
        if (glm::distance(p, place) <= tolerance) {
          index = copy, found = true;
          break;
        }
      if (!found) {
        index = uint32_t(mesh.positions.size() + split.copied_from.size());
        split.copied_from.push_back(v);
        list.emplace_back(place, index);
      }
      split.triangles[t][k] = index;
    }
  }
  if (split.copied_from.empty()) split.triangles.clear();
  return split;
}

// Turns a chart in its plane to the rotation with the smallest bounding rectangle, then lays it
// down (wider than tall), so that its rectangle wastes less and shelves pack tighter. The
// smallest rectangle has a side along an edge of the chart's convex hull, so trying the
// directions of its triangles' edges (up to kMaxChartRotations of them, evenly picked) finds it
// or comes close. Vertices at one position keep one coordinate (the rotation is a function of
// the position), as the welded chart growing needs.
constexpr size_t kMaxChartRotations = 64;

void orient_chart(const Mesh& mesh, ChartBuild& chart, std::vector<vec2>& local) {
  constexpr float kQuarter = 1.57079632679f;
  std::vector<float> angles;
  for (uint32_t t : chart.triangles)
    for (int k = 0; k < 3; ++k) {
      const vec2 d = local[mesh.triangles[t][(k + 1) % 3]] - local[mesh.triangles[t][k]];
      if (glm::dot(d, d) > 0.0f)
        angles.push_back(std::fmod(std::atan2(d.y, d.x) + 4 * kQuarter, kQuarter));
    }
  std::sort(angles.begin(), angles.end());
  angles.erase(
      std::unique(angles.begin(), angles.end(), [](float a, float b) { return b - a < 1e-4f; }),
      angles.end());
  if (angles.size() > kMaxChartRotations) {
    std::vector<float> picked;
    for (size_t k = 0; k < kMaxChartRotations; ++k)
      picked.push_back(angles[k * angles.size() / kMaxChartRotations]);
    angles = std::move(picked);
  }
  const auto rotated = [&](vec2 p, float c, float s) {
    return vec2(c * p.x + s * p.y, c * p.y - s * p.x);
  };
  float best_angle = 0.0f;
  float best_area = (chart.hi.x - chart.lo.x) * (chart.hi.y - chart.lo.y);
  for (float angle : angles) {
    const float c = std::cos(angle), s = std::sin(angle);
    vec2 lo(1e30f), hi(-1e30f);
    for (uint32_t v : chart.vertices) {
      const vec2 p = rotated(local[v], c, s);
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
    const float area = (hi.x - lo.x) * (hi.y - lo.y);
    if (area < best_area * 0.999f) {  // keep the plain projection unless clearly better
      best_area = area;
      best_angle = angle;
    }
  }
  const float c = std::cos(best_angle), s = std::sin(best_angle);
  chart.lo = vec2(1e30f);
  chart.hi = vec2(-1e30f);
  for (uint32_t v : chart.vertices) {
    if (best_angle != 0.0f) local[v] = rotated(local[v], c, s);
    chart.lo = glm::min(chart.lo, local[v]);
    chart.hi = glm::max(chart.hi, local[v]);
  }
  if (chart.hi.y - chart.lo.y > chart.hi.x - chart.lo.x) {
    for (uint32_t v : chart.vertices) local[v] = vec2(local[v].y, -local[v].x);
    const vec2 lo = chart.lo, hi = chart.hi;
    chart.lo = vec2(lo.y, -hi.x);
    chart.hi = vec2(hi.y, -lo.x);
  }
}

// Projects a chart onto the plane of its mean normal and orients it. Returns false if the chart
// bends too far to be projected flat (only possible with a chart angle near 90 degrees).
bool project_chart(const Mesh& mesh, ChartBuild& chart, std::vector<vec2>& local) {
  const vec3 n = area_weighted_normal(mesh, chart.triangles);
  for (uint32_t t : chart.triangles)
    if (glm::dot(triangle_normal(mesh, t), n) < 0.1f) return false;
  const Frame frame(n);
  collect_vertices(mesh, chart);
  for (uint32_t v : chart.vertices) {
    const vec3 p = mesh.positions[v];
    local[v] = {glm::dot(p, frame.tangent), glm::dot(p, frame.bitangent)};
    chart.lo = glm::min(chart.lo, local[v]);
    chart.hi = glm::max(chart.hi, local[v]);
  }
  orient_chart(mesh, chart, local);
  return true;
}

// A chart at most this many texels across (its oriented rectangle's short side) pays more in
// padding than it holds, so it is unfolded into a strip with its thin neighbours
// (atlas_unfold.h).
constexpr float kThinTexels = 4.0f;
// A flat chart only this narrow: unfolded across a crease, a face 3 texels wide has a third of
// its texels straddling the edge, mixing the light of faces at 90 degrees (the Cornell box's
// blocks at 5 texels/m: 7.9% error with them unfolded, 5.9% as charts of their own).
constexpr float kThinFlatTexels = 2.0f;
// Charts whose normals all lie this close to their first triangle's are flat.
constexpr float kFlatCosine = 0.9999f;
// A flat chart next to a thin one is unfolded with it only up to this many triangles, so that a
// finely meshed wall stays one projected chart (unfolded charts stop at 2048 triangles).
constexpr size_t kMaxUnfoldedFlatTriangles = 256;

// Renumbers charts by their first triangle, so ids follow triangle order as the seeds did.
int renumber_charts(std::vector<int>& chart_of, int chart_count, std::vector<uint8_t>& unfolded) {
  std::vector<int> new_id(size_t(chart_count), -1);
  std::vector<uint8_t> flags;
  int next = 0;
  for (int& c : chart_of) {
    if (c < 0) continue;
    if (new_id[size_t(c)] < 0) {
      new_id[size_t(c)] = next++;
      flags.push_back(unfolded[size_t(c)]);
    }
    c = new_id[size_t(c)];
  }
  unfolded = std::move(flags);
  return next;
}

// Cuts a mesh into charts (splitting shared vertices into `split`, and the split mesh into
// `split_mesh` when there is one): charts of similar normals projected onto their plane, and
// the thin ones among them, with the small flat charts next to them, unfolded into strips.
// Returns false if a chart bends too far to be projected flat.
bool unwrap_mesh(const Mesh& original, int mesh_index, float cos_limit, float texel,
                 VertexSplit& split, Mesh& split_mesh, std::vector<vec2>& local,
                 std::vector<ChartBuild>& out) {
  auto neighbours = face_neighbours(original);
  // No chart grows, or unfolds, across from a hidden triangle to an open one (Mesh::hidden,
  // contact_conform.h): a chart that ran under a wall or a block would share texels between
  // the light on one side and the dark, or the other room, on the other.
  if (original.hidden.size() == original.triangles.size())
    for (size_t t = 0; t < neighbours.size(); ++t)
      std::erase_if(neighbours[t],
                    [&](uint32_t nb) { return original.hidden[nb] != original.hidden[t]; });
  std::vector<int> chart_of;
  int chart_count = grow_charts(original, neighbours, cos_limit, chart_of);
  // Which charts are thin, from their projection onto the unsplit mesh (one chart at a time,
  // so the vertices they share do not matter); they are unfolded together with the flat charts
  // next to them (a tabletop with its rim around it), the largest chart seeding first.
  std::vector<ChartBuild> trial(static_cast<size_t>(chart_count));
  for (size_t t = 0; t < original.triangles.size(); ++t)
    if (chart_of[t] >= 0) trial[size_t(chart_of[t])].triangles.push_back(uint32_t(t));
  local.assign(original.positions.size(), vec2(0.0f));
  std::vector<uint8_t> thin(size_t(chart_count), 0), flat(size_t(chart_count), 0);
  std::vector<double> chart_area(size_t(chart_count), 0.0);
  for (size_t c = 0; c < trial.size(); ++c) {
    const ChartBuild& chart = trial[c];
    const vec3 n0 = triangle_normal(original, chart.triangles.front());
    flat[c] = 1;
    for (uint32_t t : chart.triangles) {
      flat[c] = flat[c] && glm::dot(triangle_normal(original, t), n0) > kFlatCosine;
      chart_area[c] += triangle_area(original, t);
    }
    const float thin_texels = flat[c] ? kThinFlatTexels : kThinTexels;
    if (project_chart(original, trial[c], local))
      thin[c] = std::min(chart.hi.x - chart.lo.x, chart.hi.y - chart.lo.y) <= thin_texels * texel;
  }
  std::vector<uint8_t> pool = thin;
  for (size_t t = 0; t < original.triangles.size(); ++t)
    for (uint32_t nb : neighbours[t])
      if (chart_of[t] >= 0 && chart_of[nb] >= 0 && thin[size_t(chart_of[nb])] &&
          flat[size_t(chart_of[t])] &&
          trial[size_t(chart_of[t])].triangles.size() <= kMaxUnfoldedFlatTriangles)
        pool[size_t(chart_of[t])] = 1;
  std::vector<uint32_t> seeds;
  for (size_t t = 0; t < original.triangles.size(); ++t)
    if (chart_of[t] >= 0 && pool[size_t(chart_of[t])]) seeds.push_back(uint32_t(t));
  std::stable_sort(seeds.begin(), seeds.end(), [&](uint32_t a, uint32_t b) {
    return chart_area[size_t(chart_of[a])] > chart_area[size_t(chart_of[b])];
  });
  std::vector<std::array<vec2, 3>> corners;
  std::vector<uint8_t> unfolded;
  chart_count =
      unfold_charts(original, neighbours, seeds, texel, chart_of, chart_count, corners, unfolded);
  chart_count = renumber_charts(chart_of, chart_count, unfolded);
  split = split_shared_vertices(original, chart_of, unfolded, corners, 1e-3f * texel);
  if (!split.empty()) split_mesh = split_vertices(original, split);
  const Mesh& mesh = split.empty() ? original : split_mesh;
  local.assign(mesh.positions.size(), vec2(0.0f));
  std::vector<ChartBuild> charts(static_cast<size_t>(chart_count), ChartBuild{});
  for (size_t t = 0; t < mesh.triangles.size(); ++t)
    if (chart_of[t] >= 0) charts[size_t(chart_of[t])].triangles.push_back(uint32_t(t));
  for (size_t c = 0; c < charts.size(); ++c) {
    ChartBuild& chart = charts[c];
    chart.mesh = mesh_index;
    if (!unfolded[c]) {
      if (!project_chart(mesh, chart, local)) return false;
      continue;
    }
    // Corners that share a split vertex lie within the split's tolerance: the first one holds.
    collect_vertices(mesh, chart);
    std::vector<uint8_t> set(chart.vertices.size(), 0);
    for (uint32_t t : chart.triangles)
      for (int k = 0; k < 3; ++k) {
        const uint32_t v = mesh.triangles[t][k];
        const size_t slot =
            size_t(std::lower_bound(chart.vertices.begin(), chart.vertices.end(), v) -
                   chart.vertices.begin());
        if (set[slot]) continue;
        set[slot] = 1;
        local[v] = corners[t][size_t(k)];
        chart.lo = glm::min(chart.lo, local[v]);
        chart.hi = glm::max(chart.hi, local[v]);
      }
    orient_chart(mesh, chart, local);
  }
  for (ChartBuild& chart : charts) out.push_back(std::move(chart));
  return true;
}

// A mesh with its own lightmap UVs keeps their layout island by island (given_uvs.h): each
// island is a chart, scaled so that one UV unit spans the metres the mesh's area implies (the
// same scale for every island of the mesh, so its texel density is uniform).
bool charts_from_given_uvs(const Mesh& mesh, int mesh_index, const GivenUvCheck& check,
                           std::vector<vec2>& local, std::vector<ChartBuild>& out) {
  double world_area = 0.0, uv_area = 0.0;
  std::vector<ChartBuild> islands(size_t(check.islands));
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (check.island[t] < 0) continue;
    const uvec3 tri = mesh.triangles[t];
    const vec2 a = mesh.lightmap_uvs[tri.x], b = mesh.lightmap_uvs[tri.y],
               c = mesh.lightmap_uvs[tri.z];
    const vec2 e1 = b - a, e2 = c - a;
    uv_area += 0.5 * std::abs(double(e1.x) * e2.y - double(e1.y) * e2.x);
    world_area += triangle_area(mesh, t);
    islands[size_t(check.island[t])].triangles.push_back(uint32_t(t));
  }
  if (!(uv_area > 0.0) || !(world_area > 0.0)) return false;
  const float metres_per_uv = float(std::sqrt(world_area / uv_area));
  // Zero-area triangles join the island of a vertex they share (they take its texels' light),
  // else the first island.
  std::vector<int> island_of_vertex(mesh.positions.size(), -1);
  for (size_t t = 0; t < mesh.triangles.size(); ++t)
    if (check.island[t] >= 0)
      for (int k = 0; k < 3; ++k) island_of_vertex[mesh.triangles[t][k]] = check.island[t];
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (check.island[t] >= 0) continue;
    int island = 0;
    for (int k = 0; k < 3; ++k)
      if (island_of_vertex[mesh.triangles[t][k]] >= 0)
        island = island_of_vertex[mesh.triangles[t][k]];
    islands[size_t(island)].triangles.push_back(uint32_t(t));
  }
  for (ChartBuild& chart : islands) {
    chart.mesh = mesh_index;
    chart.given_uvs = true;
    collect_vertices(mesh, chart);
    for (uint32_t v : chart.vertices) {
      local[v] = mesh.lightmap_uvs[v] * metres_per_uv;
      chart.lo = glm::min(chart.lo, local[v]);
      chart.hi = glm::max(chart.hi, local[v]);
    }
    out.push_back(std::move(chart));
  }
  return true;
}

// ---- packing ------------------------------------------------------------------------------

// Shelf packing of the chart rectangles (tallest first) at a given atlas width; returns the
// atlas size and sets each chart's offset.
glm::ivec2 pack_shelves_at(std::vector<ChartBuild>& charts, const std::vector<size_t>& order,
                           int width, int padding, int border) {
  int x = border, y = border, shelf = 0;
  for (size_t index : order) {
    ChartBuild& c = charts[index];
    c.upright = false;
    if (x + c.size.x + padding > width) {
      y += shelf + padding;
      x = border;
      shelf = 0;
    }
    c.offset = {x, y};
    x += c.size.x + padding;
    shelf = std::max(shelf, c.size.y);
  }
  return {width, y + shelf + padding};
}

// Skyline packing (bottom-left rule) of the same rectangles at a given width: each chart goes
// where its top ends lowest, so short charts fill the space above a shelf's shorter members
// that shelves leave empty. Quadratic in the chart count (the skyline has up to one segment
// per chart), so pack_charts uses it only up to kMaxSkylineCharts.
glm::ivec2 pack_skyline_at(std::vector<ChartBuild>& charts, const std::vector<size_t>& order,
                           int width, int padding, int border, bool turn) {
  struct Segment {
    int x, width, y;  // the free space starts at height y over [x, x + width)
  };
  std::vector<Segment> skyline = {{border, width - border, border}};
  int top = border;
  for (size_t index : order) {
    ChartBuild& c = charts[index];
    // The lowest top over the positions (and with `turn`, both ways round: lying first).
    size_t best = skyline.size();
    int best_y = 0, best_top = 0;
    bool best_upright = false;
    for (int way = 0; way < (turn ? 2 : 1); ++way) {
      c.upright = way == 1;
      const glm::ivec2 size = c.placed();
      const int need = size.x + padding;  // the chart and the gap after it
      for (size_t i = 0; i < skyline.size(); ++i) {
        const int x = skyline[i].x;
        if (x + need > width) break;
        int y = 0;
        for (size_t j = i; j < skyline.size() && skyline[j].x < x + need; ++j)
          y = std::max(y, skyline[j].y);
        if (best == skyline.size() || y + size.y < best_top ||
            (y + size.y == best_top && y < best_y)) {
          best = i;
          best_y = y;
          best_top = y + size.y;
          best_upright = c.upright;
        }
      }
    }
    c.upright = best_upright;
    const int need = c.placed().x + padding;
    if (best == skyline.size()) {  // wider than the atlas: cannot happen at pack()'s widths
      best = 0;
      best_y = top;
    }
    const int x = skyline[best].x;
    c.offset = {x, best_y};
    const int raised = best_y + c.placed().y + padding;
    top = std::max(top, raised);
    // Replace the covered part [x, end) of the skyline by one raised segment (the segments are
    // sorted and contiguous, so it goes in after the first covered one's uncovered left part).
    const int end = x + need;
    std::vector<Segment> next;
    next.reserve(skyline.size() + 2);
    bool inserted = false;
    for (const Segment& s : skyline) {
      const int s_end = s.x + s.width;
      if (s_end <= x || s.x >= end) {
        next.push_back(s);
        continue;
      }
      if (s.x < x) next.push_back({s.x, x - s.x, s.y});
      if (!inserted) next.push_back({x, need, raised});
      inserted = true;
      if (s_end > end) next.push_back({end, s_end - end, s.y});
    }
    // Merge neighbours at the same height, so the skyline stays short.
    skyline.clear();
    for (const Segment& s : next) {
      if (!skyline.empty() && skyline.back().y == s.y &&
          skyline.back().x + skyline.back().width == s.x)
        skyline.back().width += s.width;
      else
        skyline.push_back(s);
    }
  }
  return {width, top};
}

// Shelf or skyline packing (the skyline also with quarter turns, each in two orders) at the
// width, among kPackingWidths from the widest chart to twice the square root of the charts'
// area, that gives the squarest atlas within kPackingSlack of the smallest one that fits
// max_size (if none fits, the smallest); returns its size. A squarer atlas 2 % larger was the
// rule until strips left the room's walls to decide the shape; now the smallest wins (tall
// atlases, one wall wide). Measured against xatlas at the same density and padding:
// docs/export.md ("Atlas packing against xatlas").
constexpr int kPackingWidths = 48;
constexpr int kPackingOrders = 2;
constexpr size_t kMaxSkylineCharts = 4096;
// The turned skyline and the second order quadruple the skyline's tries: only up to this many.
constexpr size_t kMaxExtraTryCharts = 1024;
constexpr double kPackingSlack = 1.005;

glm::ivec2 pack_charts(std::vector<ChartBuild>& charts, int padding, int max_size) {
  // Two orders: tallest first (shelves) and longest side first (skyline with turns).
  std::vector<size_t> orders[kPackingOrders];
  for (std::vector<size_t>& order : orders) {
    order.resize(charts.size());
    std::iota(order.begin(), order.end(), 0);
  }
  std::stable_sort(orders[0].begin(), orders[0].end(), [&](size_t a, size_t b) {
    if (charts[a].size.y != charts[b].size.y) return charts[a].size.y > charts[b].size.y;
    return charts[a].size.x > charts[b].size.x;
  });
  std::stable_sort(orders[1].begin(), orders[1].end(), [&](size_t a, size_t b) {
    const glm::ivec2 p = charts[a].size, q = charts[b].size;
    if (std::max(p.x, p.y) != std::max(q.x, q.y)) return std::max(p.x, p.y) > std::max(q.x, q.y);
    return p.x * p.y > q.x * q.y;
  });
  double total = 0.0;
  int widest = 0;
  for (const ChartBuild& c : charts) {
    total += double(c.size.x + padding) * double(c.size.y + padding);
    widest = std::max(widest, c.size.x);
  }
  // Each rectangle is packed with the gap after it; the last one in a row or column needs only
  // the border after it, which lies `trim` inside the width the packers are given. The border
  // leaves half a gap of free nodes (none at padding 2 or 3): the lightmap is read with
  // CLAMP_TO_EDGE and no chart's bilinear footprint leaves its nodes, so it needs no more.
  const int border = padding / 2, trim = padding - border;
  const int narrowest = widest + border + padding;
  const int broadest = std::max(narrowest, int(std::ceil(2.0 * std::sqrt(total))) + padding);
  struct Try {
    int width;
    int method;  // 0 shelves, 1 skyline, 2 skyline with turns
    int order;
    glm::ivec2 size;
    bool fits;
    double area, aspect;
  };
  const auto pack_at = [&](const Try& t) {
    const std::vector<size_t>& order = orders[t.order];
    const glm::ivec2 size =
        t.method == 0 ? pack_shelves_at(charts, order, t.width, padding, border)
                      : pack_skyline_at(charts, order, t.width, padding, border, t.method == 2);
    return size - trim;
  };
  std::vector<Try> tries;
  bool any_fits = false;
  double smallest = 1e300;
  for (int k = 0; k < kPackingWidths; ++k)
    for (int method = 0; method < 3; ++method)
      for (int order = 0; order < kPackingOrders; ++order) {
        Try t;
        t.width = narrowest + int(int64_t(broadest - narrowest) * k / (kPackingWidths - 1));
        t.method = method;
        t.order = order;
        if (method > 0 && charts.size() > kMaxSkylineCharts) continue;
        if ((method == 2 || order > 0) && charts.size() > kMaxExtraTryCharts) continue;
        t.size = pack_at(t);
        t.fits = t.size.x <= max_size && t.size.y <= max_size;
        t.area = double(t.size.x) * double(t.size.y);
        t.aspect = double(std::max(t.size.x, t.size.y)) / double(std::min(t.size.x, t.size.y));
        any_fits = any_fits || t.fits;
        tries.push_back(t);
      }
  for (const Try& t : tries)
    if (t.fits == any_fits) smallest = std::min(smallest, t.area);
  const Try* best = nullptr;
  for (const Try& t : tries) {
    if (t.fits != any_fits || t.area > smallest * kPackingSlack) continue;
    if (!best || t.aspect < best->aspect) best = &t;
  }
  return pack_at(*best);
}

// ---- exact node areas -----------------------------------------------------------------------

// Integrals of the four bilinear weights of the unit cell over a polygon in cell coordinates
// (edge-midpoint rule per fan triangle: exact for the quadratic weights).
void integrate_weights(const ClipPolygon& poly, double w[4]) {
  auto add = [&](vec2 m, double scale) {
    const double x = m.x, y = m.y;
    w[0] += scale * (1 - x) * (1 - y);
    w[1] += scale * x * (1 - y);
    w[2] += scale * (1 - x) * y;
    w[3] += scale * x * y;
  };
  for (int k = 1; k + 1 < poly.n; ++k) {
    const vec2 a = poly.p[0], b = poly.p[k], c = poly.p[k + 1];
    const double area = fan_piece_area(poly, k);
    if (area <= 0.0) continue;
    add(0.5f * (a + b), area / 3.0);
    add(0.5f * (b + c), area / 3.0);
    add(0.5f * (c + a), area / 3.0);
  }
}

void accumulate_node_areas(const Atlas& atlas, const Mesh& mesh, const std::vector<vec2>& uvs,
                           uint32_t triangle, std::vector<double>& area) {
  const uvec3 tri = mesh.triangles[triangle];
  const vec2 scale(float(atlas.width), float(atlas.height));
  // Node space: node (i, j) sits at integer coordinates.
  const vec2 q[3] = {uvs[tri.x] * scale - 0.5f, uvs[tri.y] * scale - 0.5f,
                     uvs[tri.z] * scale - 0.5f};
  const double uv_area = 0.5 * std::abs(double(q[1].x - q[0].x) * (q[2].y - q[0].y) -
                                        double(q[1].y - q[0].y) * (q[2].x - q[0].x));
  const double world_area = triangle_area(mesh, triangle);
  if (!(uv_area > 0.0) || !(world_area > 0.0)) return;
  const double world_per_uv = world_area / uv_area;
  const vec2 lo = glm::min(q[0], glm::min(q[1], q[2]));
  const vec2 hi = glm::max(q[0], glm::max(q[1], q[2]));
  // Scanlines: per row of cells, the triangle's span on the row's two lines tells which cells
  // are wholly inside (each corner's weight integrates to 1/4 there); the cells at the ends
  // are clipped exactly.
  auto span = [&](double y, double& left, double& right) {
    left = 1e300, right = -1e300;
    for (int k = 0; k < 3; ++k) {
      const vec2 a = q[k], b = q[(k + 1) % 3];
      if (!((a.y <= y && y <= b.y) || (b.y <= y && y <= a.y))) continue;
      if (a.y == b.y) {
        left = std::min({left, double(a.x), double(b.x)});
        right = std::max({right, double(a.x), double(b.x)});
      } else {
        const double x = a.x + (y - a.y) / (double(b.y) - a.y) * (double(b.x) - a.x);
        left = std::min(left, x), right = std::max(right, x);
      }
    }
    return left <= right;
  };
  for (int j = int(std::floor(lo.y)); j <= int(std::floor(hi.y)); ++j) {
    double x_min = 1e300, x_max = -1e300;
    for (int k = 0; k < 3; ++k)
      if (q[k].y >= float(j) && q[k].y <= float(j + 1))
        x_min = std::min(x_min, double(q[k].x)), x_max = std::max(x_max, double(q[k].x));
    double l0, r0, l1, r1;
    const bool on0 = span(j, l0, r0), on1 = span(j + 1, l1, r1);
    if (on0) x_min = std::min(x_min, l0), x_max = std::max(x_max, r0);
    if (on1) x_min = std::min(x_min, l1), x_max = std::max(x_max, r1);
    if (x_min > x_max) continue;
    int full_lo = 1, full_hi = 0;
    if (on0 && on1) {
      full_lo = int(std::ceil(std::max(l0, l1)));
      full_hi = int(std::floor(std::min(r0, r1))) - 1;
    }
    const int first = int(std::floor(x_min));
    const int last = std::max(first, int(std::ceil(x_max)) - 1);
    for (int i = first; i <= last; ++i) {
      if (i >= full_lo && i <= full_hi) {
        area[atlas.node_index(i, j)] += 0.25 * world_per_uv;
        area[atlas.node_index(i + 1, j)] += 0.25 * world_per_uv;
        area[atlas.node_index(i, j + 1)] += 0.25 * world_per_uv;
        area[atlas.node_index(i + 1, j + 1)] += 0.25 * world_per_uv;
        continue;
      }
      const vec2 cell{float(i), float(j)};
      const ClipPolygon poly = clip_to_unit_square(q[0] - cell, q[1] - cell, q[2] - cell);
      if (poly.n < 3) continue;
      double w[4] = {0, 0, 0, 0};
      integrate_weights(poly, w);
      const int ni[4] = {i, i + 1, i, i + 1}, nj[4] = {j, j, j + 1, j + 1};
      for (int k = 0; k < 4; ++k) {
        if (ni[k] < 0 || nj[k] < 0 || ni[k] >= atlas.width || nj[k] >= atlas.height) continue;
        area[atlas.node_index(ni[k], nj[k])] += w[k] * world_per_uv;
      }
    }
  }
}

// Counts sample points (4 per texel) covered by more than one triangle of the chart.
size_t overlapping_samples(const Atlas& atlas, const Mesh& mesh, const std::vector<vec2>& uvs,
                           const AtlasChart& chart) {
  constexpr int kSub = 2;
  const int sw = (chart.size.x + 2) * kSub, sh = (chart.size.y + 2) * kSub;
  std::vector<uint8_t> count(size_t(sw) * size_t(sh), 0);
  const vec2 scale(float(atlas.width), float(atlas.height));
  const vec2 origin = vec2(chart.offset) - 1.0f;
  size_t overlaps = 0;
  for (uint32_t t : chart.triangles) {
    const uvec3 tri = mesh.triangles[t];
    const vec2 a = (uvs[tri.x] * scale - origin) * float(kSub);
    const vec2 b = (uvs[tri.y] * scale - origin) * float(kSub);
    const vec2 c = (uvs[tri.z] * scale - origin) * float(kSub);
    const float det = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    if (std::abs(det) < 1e-12f) continue;
    const vec2 lo = glm::min(a, glm::min(b, c)), hi = glm::max(a, glm::max(b, c));
    for (int y = std::max(0, int(lo.y)); y <= std::min(sh - 1, int(hi.y)); ++y) {
      for (int x = std::max(0, int(lo.x)); x <= std::min(sw - 1, int(hi.x)); ++x) {
        const vec2 p(float(x) + 0.5f, float(y) + 0.5f);
        const float b1 = ((p.x - a.x) * (c.y - a.y) - (p.y - a.y) * (c.x - a.x)) / det;
        const float b2 = ((b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x)) / det;
        constexpr float eps = 1e-3f;  // shared edges are not overlaps
        if (b1 > eps && b2 > eps && 1.0f - b1 - b2 > eps) {
          uint8_t& n = count[size_t(y) * size_t(sw) + size_t(x)];
          if (n == 1) ++overlaps;
          n = uint8_t(std::min(2, n + 1));
        }
      }
    }
  }
  return overlaps;
}

}  // namespace

// ---- public -------------------------------------------------------------------------------

// A chart's edges lie at least this far (texels) inside the node centres at offset - 1 and
// offset + size, so float rounding of its UVs never reaches a node outside its rectangle grown
// by one (atlas.h).
constexpr float kNodeInset = 2e-3f;

float automatic_texel_size(const Scene& scene, const std::vector<bool>& include, int max_size) {
  double area = 0.0;
  for (size_t m = 0; m < scene.meshes.size(); ++m)
    if (m < include.size() && include[m]) area += mesh_area(scene.meshes[m]);
  const float by_scale = scene_bounds(scene).diagonal() / 256.0f;
  const float by_budget = float(std::sqrt(area / (0.25 * double(max_size) * double(max_size))));
  return std::max({by_scale, by_budget, 1e-6f});
}

Atlas build_atlas(const Scene& scene, const std::vector<bool>& include, const AtlasParams& params) {
  Atlas atlas;
  atlas.lightmap_uvs.resize(scene.meshes.size());
  const int padding = std::max(2, params.padding);
  const float cos_limit = std::cos(glm::radians(params.chart_angle_deg));
  atlas.texel_size = params.texel_size > 0.0f
                         ? params.texel_size
                         : automatic_texel_size(scene, include, params.max_size);

  // The meshes as the atlas lays them out: with their shared vertices split where that was
  // needed (`split_meshes[m]` is empty otherwise).
  std::vector<Mesh> split_meshes(scene.meshes.size());
  auto laid_out = [&](size_t m) -> const Mesh& {
    return atlas.vertex_splits[m].empty() ? scene.meshes[m] : split_meshes[m];
  };
  std::vector<std::vector<vec2>> local(scene.meshes.size());
  atlas.vertex_splits.resize(scene.meshes.size());
  std::vector<ChartBuild> charts;
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    if (m >= include.size() || !include[m]) continue;
    const Mesh& mesh = scene.meshes[m];
    const size_t first = charts.size();
    const bool given = mesh.lightmap_uvs.size() == mesh.positions.size();
    const float chosen = m < params.mesh_texel_size.size() ? params.mesh_texel_size[m] : 0.0f;
    const float texel = mesh.bake.texel_size > 0.0f ? mesh.bake.texel_size
                        : chosen > 0.0f             ? chosen
                                                    : atlas.texel_size;
    bool ok = false;
    GivenUvCheck check;
    bool keep = given && !params.generate_lightmap_uvs;
    if (keep) {
      check = check_given_uvs(mesh);
      if (check.folds() || check.zero_area > 0)
        atlas.warnings.push_back("mesh '" + mesh.name + "': its lightmap UVs have " +
                                 check.describe() +
                                 (check.folds() ? "; generated new ones (two surfaces would "
                                                  "share texels)"
                                                : "; kept (those triangles take the light of "
                                                  "a point)"));
      keep = !check.folds();
    }
    if (keep) {
      local[m].assign(mesh.positions.size(), vec2(0.0f));
      ok = charts_from_given_uvs(mesh, int(m), check, local[m], charts);
    } else {
      ok = unwrap_mesh(mesh, int(m), cos_limit, texel, atlas.vertex_splits[m], split_meshes[m],
                       local[m], charts);
    }
    if (!ok) {
      charts.resize(first);
      local[m].clear();
      atlas.vertex_splits[m] = {};
      split_meshes[m] = {};
      atlas.warnings.push_back("mesh '" + mesh.name + "': " +
                               (keep ? "its lightmap UVs have zero area"
                                      : "a chart bends too far to unwrap flat (lower "
                                        "chart_angle_deg)") +
                               "; it gets no illumination map");
      continue;
    }
    for (size_t c = first; c < charts.size(); ++c) charts[c].texel_size = texel;
  }
  if (charts.empty()) return atlas;

  // Grow the texels until the packing fits.
  float growth = 1.0f;
  glm::ivec2 size;
  for (;;) {
    for (ChartBuild& c : charts) {
      const vec2 extent = (c.hi - c.lo) / (c.texel_size * growth);
      c.size = glm::max(glm::ivec2(glm::ceil(extent + 2.0f * kNodeInset)) - 1, glm::ivec2(0));
    }
    size = pack_charts(charts, padding, params.max_size);
    if (size.x <= params.max_size && size.y <= params.max_size) break;
    // Charts of one texel plus padding that still do not fit: no texel size will help.
    if (growth > 1e4f)
      throw std::runtime_error("illumination atlas: " + std::to_string(charts.size()) +
                               " charts do not fit in " + std::to_string(params.max_size) +
                               "^2 texels with padding " + std::to_string(padding));
    growth *= 1.2f;
  }
  if (growth > 1.0f)
    atlas.warnings.push_back("texels grown " + std::to_string(growth) + "x to fit the atlas in " +
                             std::to_string(params.max_size) + "^2");
  atlas.texel_size *= growth;
  atlas.width = size.x;
  atlas.height = size.y;

  // Atlas UVs per vertex.
  const vec2 inv_size(1.0f / float(atlas.width), 1.0f / float(atlas.height));
  atlas.mesh_texel_size.assign(scene.meshes.size(), 0.0f);
  for (ChartBuild& c : charts) {
    atlas.mesh_texel_size[size_t(c.mesh)] = c.texel_size * growth;
    std::vector<vec2>& uvs = atlas.lightmap_uvs[size_t(c.mesh)];
    if (uvs.empty()) uvs.assign(laid_out(size_t(c.mesh)).positions.size(), vec2(0.5f));
    const float texel = c.texel_size * growth;
    // Centred between the node centres at offset - 1 and offset + size, so the outermost nodes
    // each hold at least 1/8 of a node's area (no sliver nodes with noisy light).
    const vec2 extent = (c.hi - c.lo) / texel;
    const vec2 placed = c.upright ? vec2(extent.y, extent.x) : extent;
    const vec2 start = vec2(c.offset) - 0.5f + 0.5f * (vec2(c.placed()) + 1.0f - placed);
    for (uint32_t v : c.vertices) {
      vec2 d = (local[size_t(c.mesh)][v] - c.lo) / texel;
      if (c.upright) d = vec2(extent.y - d.y, d.x);  // a quarter turn
      uvs[v] = (start + d) * inv_size;
    }
    AtlasChart chart;
    chart.mesh = c.mesh;
    chart.triangles = std::move(c.triangles);
    chart.offset = c.offset;
    chart.size = c.placed();
    chart.texel_size = texel;
    chart.given_uvs = c.given_uvs;
    atlas.charts.push_back(std::move(chart));
  }

  // Exact node areas, then the valid mask.
  std::vector<double> area(size_t(atlas.width) * size_t(atlas.height), 0.0);
  // Charts never share a node (see the padding rule), so they can run in parallel and each
  // node still sums its contributions in one fixed order.
  std::vector<size_t> overlap_counts(atlas.charts.size(), 0);
  tbb::parallel_for(size_t(0), atlas.charts.size(), [&](size_t c) {
    const AtlasChart& chart = atlas.charts[c];
    const Mesh& mesh = laid_out(size_t(chart.mesh));
    for (uint32_t t : chart.triangles)
      accumulate_node_areas(atlas, mesh, atlas.lightmap_uvs[size_t(chart.mesh)], t, area);
    // A flat chart projected onto its own plane cannot fold; given UVs, bent and unfolded
    // charts can.
    bool flat = true;
    const vec3 n0 = triangle_normal(mesh, chart.triangles.front());
    for (uint32_t t : chart.triangles)
      flat = flat && glm::dot(triangle_normal(mesh, t), n0) > kFlatCosine;
    if (chart.given_uvs || !flat)
      overlap_counts[c] =
          overlapping_samples(atlas, mesh, atlas.lightmap_uvs[size_t(chart.mesh)], chart);
  });
  for (size_t c = 0; c < atlas.charts.size(); ++c) {
    const AtlasChart& chart = atlas.charts[c];
    const Mesh& mesh = scene.meshes[size_t(chart.mesh)];
    const size_t overlaps = overlap_counts[c];
    if (overlaps > 0)
      atlas.warnings.push_back("mesh '" + mesh.name + "': " + std::to_string(overlaps) +
                               " samples of its " +
                               (chart.given_uvs ? "given lightmap UVs" : "unwrapped chart") +
                               " overlap; light there is shared between faces");
  }
  atlas.texel_area.resize(area.size());
  atlas.valid.resize(area.size());
  for (size_t k = 0; k < area.size(); ++k) {
    atlas.texel_area[k] = float(area[k]);
    atlas.valid[k] = area[k] > 0.0 ? 1 : 0;
  }
  return atlas;
}

NodeWeights node_weights_at_uv(const Atlas& atlas, vec2 uv) {
  const vec2 s = uv * vec2(float(atlas.width), float(atlas.height)) - 0.5f;
  const vec2 base = glm::floor(s);
  const vec2 f = s - base;
  const int i0 = std::clamp(int(base.x), 0, atlas.width - 1);
  const int j0 = std::clamp(int(base.y), 0, atlas.height - 1);
  const int i1 = std::min(i0 + 1, atlas.width - 1), j1 = std::min(j0 + 1, atlas.height - 1);
  NodeWeights nw;
  nw.index[0] = atlas.node_index(i0, j0);
  nw.index[1] = atlas.node_index(i1, j0);
  nw.index[2] = atlas.node_index(i0, j1);
  nw.index[3] = atlas.node_index(i1, j1);
  nw.weight[0] = (1 - f.x) * (1 - f.y);
  nw.weight[1] = f.x * (1 - f.y);
  nw.weight[2] = (1 - f.x) * f.y;
  nw.weight[3] = f.x * f.y;
  return nw;
}

bool node_weights(const Atlas& atlas, const Scene& scene, uint32_t mesh, uint32_t triangle,
                  vec2 barycentric, NodeWeights& out) {
  if (!atlas.has_map(mesh)) return false;
  const uvec3 tri = atlas.triangles_of(scene, mesh)[triangle];
  const std::vector<vec2>& uvs = atlas.lightmap_uvs[mesh];
  const vec2 uv = (1.0f - barycentric.x - barycentric.y) * uvs[tri.x] + barycentric.x * uvs[tri.y] +
                  barycentric.y * uvs[tri.z];
  out = node_weights_at_uv(atlas, uv);
  return true;
}

std::vector<vec3> power_to_radiance(const Atlas& atlas, const std::vector<glm::dvec3>& power) {
  std::vector<vec3> radiance(power.size(), vec3(0.0f));
  for (size_t k = 0; k < power.size(); ++k)
    if (atlas.texel_area[k] > 0.0f)
      radiance[k] = vec3(power[k] / (double(atlas.texel_area[k]) * std::numbers::pi));
  return radiance;
}

void dilate(const Atlas& atlas, std::vector<vec3>& radiance, int rings) {
  // Valid nodes only lie in the charts' rectangles grown by one node, so the nodes to fill
  // lie within `rings` more of them.
  std::vector<size_t> candidates;
  for (const AtlasChart& chart : atlas.charts) {
    const glm::ivec2 lo = glm::max(chart.offset - 1 - rings, glm::ivec2(0));
    const glm::ivec2 hi =
        glm::min(chart.offset + chart.size + rings, glm::ivec2(atlas.width - 1, atlas.height - 1));
    for (int j = lo.y; j <= hi.y; ++j)
      for (int i = lo.x; i <= hi.x; ++i)
        if (!atlas.valid[atlas.node_index(i, j)]) candidates.push_back(atlas.node_index(i, j));
  }
  std::sort(candidates.begin(), candidates.end());
  candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
  std::vector<uint8_t> filled = atlas.valid;
  std::vector<std::pair<size_t, vec3>> updates;
  for (int ring = 0; ring < rings; ++ring) {
    updates.clear();
    for (size_t index : candidates) {
      if (filled[index]) continue;
      const int i = int(index % size_t(atlas.width)), j = int(index / size_t(atlas.width));
      vec3 sum(0.0f);
      int count = 0;
      for (int dj = -1; dj <= 1; ++dj) {
        for (int di = -1; di <= 1; ++di) {
          const int x = i + di, y = j + dj;
          if (x < 0 || y < 0 || x >= atlas.width || y >= atlas.height) continue;
          if (!filled[atlas.node_index(x, y)]) continue;
          sum += radiance[atlas.node_index(x, y)];
          ++count;
        }
      }
      if (count > 0) updates.emplace_back(index, sum / float(count));
    }
    for (const auto& [index, value] : updates) {
      radiance[index] = value;
      filled[index] = 1;
    }
  }
}

vec3 sample_map(const Atlas& atlas, const std::vector<vec3>& radiance, vec2 uv) {
  const NodeWeights nw = node_weights_at_uv(atlas, uv);
  vec3 value(0.0f);
  for (int k = 0; k < 4; ++k) value += nw.weight[k] * radiance[nw.index[k]];
  return value;
}

}  // namespace lb
