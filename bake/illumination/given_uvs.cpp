#include "bake/illumination/given_uvs.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <unordered_map>

namespace lb {

namespace {

using dvec2 = glm::dvec2;

double cross2(dvec2 a, dvec2 b) { return a.x * b.y - a.y * b.x; }

// Twice the signed UV area; 0 for a triangle of no area by the loaders' rule (1e-7 of its
// longest edge squared, as zero_area_triangle).
double signed_uv_area(const Mesh& mesh, uvec3 t) {
  const dvec2 a(mesh.lightmap_uvs[t.x]), b(mesh.lightmap_uvs[t.y]), c(mesh.lightmap_uvs[t.z]);
  const double area2 = cross2(b - a, c - a);
  const double longest =
      std::max({glm::dot(b - a, b - a), glm::dot(c - b, c - b), glm::dot(a - c, a - c)});
  return std::abs(area2) <= 1e-7 * longest ? 0.0 : area2;
}

// A sliver in 3D too (twice its area under 1e-4 of its longest edge squared): the loaders'
// contact cuts make such pieces, whose UVs, interpolated and rounded to float, may have no
// area left; that is no fault of the artist's UVs.
bool sliver_in_space(const Mesh& mesh, uvec3 t) {
  const glm::dvec3 a(mesh.positions[t.x]), b(mesh.positions[t.y]), c(mesh.positions[t.z]);
  const double area2 = glm::length(glm::cross(b - a, c - a));
  const double longest =
      std::max({glm::dot(b - a, b - a), glm::dot(c - b, c - b), glm::dot(a - c, a - c)});
  return area2 <= 1e-4 * longest;
}

struct UnionFind {
  std::vector<uint32_t> parent;
  explicit UnionFind(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
  uint32_t find(uint32_t v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  }
  void join(uint32_t a, uint32_t b) {
    a = find(a), b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
};

// Whether two UV triangles' interiors overlap by more than `eps` along every separating axis
// candidate (their six edge normals): triangles that only share an edge or a corner do not.
bool interiors_overlap(const dvec2 (&p)[3], const dvec2 (&q)[3], double eps) {
  for (const dvec2(*tri)[3] : {&p, &q})
    for (int k = 0; k < 3; ++k) {
      const dvec2 e = (*tri)[(k + 1) % 3] - (*tri)[k];
      const double length = glm::length(e);
      if (!(length > 0.0)) continue;
      const dvec2 n(-e.y / length, e.x / length);
      double lo_p = 1e300, hi_p = -1e300, lo_q = 1e300, hi_q = -1e300;
      for (int i = 0; i < 3; ++i) {
        lo_p = std::min(lo_p, glm::dot(n, p[i])), hi_p = std::max(hi_p, glm::dot(n, p[i]));
        lo_q = std::min(lo_q, glm::dot(n, q[i])), hi_q = std::max(hi_q, glm::dot(n, q[i]));
      }
      if (std::min(hi_p, hi_q) - std::max(lo_p, lo_q) <= eps) return false;
    }
  return true;
}

}  // namespace

std::string GivenUvCheck::describe() const {
  std::vector<std::string> parts;
  if (overlapping > 0) parts.push_back(std::to_string(overlapping) + " overlapping");
  if (flipped > 0) parts.push_back(std::to_string(flipped) + " flipped");
  if (zero_area > 0) parts.push_back(std::to_string(zero_area) + " zero-area");
  std::string text;
  for (size_t k = 0; k < parts.size(); ++k)
    text += (k == 0 ? "" : k + 1 == parts.size() ? " and " : ", ") + parts[k];
  return text + " of " + std::to_string(triangles) + " triangles";
}

GivenUvCheck check_given_uvs(const Mesh& mesh) {
  GivenUvCheck check;
  const size_t nt = mesh.triangles.size();
  check.triangles = nt;
  check.island.assign(nt, -1);
  if (mesh.lightmap_uvs.size() != mesh.positions.size() || nt == 0) return check;

  std::vector<double> area2(nt);
  UnionFind sets(mesh.positions.size());
  for (size_t t = 0; t < nt; ++t) {
    area2[t] = signed_uv_area(mesh, mesh.triangles[t]);
    if (area2[t] == 0.0) {
      if (!sliver_in_space(mesh, mesh.triangles[t])) ++check.zero_area;
      continue;
    }
    sets.join(mesh.triangles[t].x, mesh.triangles[t].y);
    sets.join(mesh.triangles[t].x, mesh.triangles[t].z);
  }
  // Vertices at the very same UV belong together (hard edges split vertices, not islands).
  std::unordered_map<uint64_t, uint32_t> first_at;
  for (uint32_t v = 0; v < mesh.positions.size(); ++v) {
    const vec2 uv = mesh.lightmap_uvs[v] + vec2(0.0f);  // -0 is +0
    uint64_t key;
    std::memcpy(&key, &uv, sizeof key);
    const auto [it, fresh] = first_at.try_emplace(key, v);
    if (!fresh) sets.join(it->second, v);
  }
  std::unordered_map<uint32_t, int> island_of_root;
  for (size_t t = 0; t < nt; ++t) {
    if (area2[t] == 0.0) continue;
    const uint32_t root = sets.find(mesh.triangles[t].x);
    check.island[t] = island_of_root.try_emplace(root, int(island_of_root.size())).first->second;
  }
  check.islands = int(island_of_root.size());

  // Flipped: against the winding that holds most of the island's area.
  std::vector<double> positive(size_t(check.islands), 0.0), negative(size_t(check.islands), 0.0);
  for (size_t t = 0; t < nt; ++t)
    if (check.island[t] >= 0)
      (area2[t] > 0.0 ? positive : negative)[size_t(check.island[t])] += std::abs(area2[t]);
  for (size_t t = 0; t < nt; ++t) {
    if (check.island[t] < 0) continue;
    const size_t i = size_t(check.island[t]);
    if ((area2[t] > 0.0) != (positive[i] >= negative[i])) ++check.flipped;
  }

  // Overlaps within an island, over a grid of about one cell per triangle.
  vec2 lo(1e30f), hi(-1e30f);
  for (const vec2& uv : mesh.lightmap_uvs) lo = glm::min(lo, uv), hi = glm::max(hi, uv);
  const vec2 extent = glm::max(hi - lo, vec2(1e-30f));
  const int side = std::clamp(int(std::sqrt(double(nt))), 1, 1024);
  const double eps = 1e-6 * double(std::max(extent.x, extent.y));
  auto cell_of = [&](float value, float low, float size) {
    return std::clamp(int((value - low) / size * float(side)), 0, side - 1);
  };
  std::vector<std::vector<uint32_t>> cells(size_t(side) * size_t(side));
  std::vector<glm::ivec4> boxes(nt);  // x0, y0, x1, y1 cells
  for (size_t t = 0; t < nt; ++t) {
    if (check.island[t] < 0) continue;
    const uvec3 tri = mesh.triangles[t];
    const vec2 a = mesh.lightmap_uvs[tri.x], b = mesh.lightmap_uvs[tri.y],
               c = mesh.lightmap_uvs[tri.z];
    const vec2 l = glm::min(a, glm::min(b, c)), h = glm::max(a, glm::max(b, c));
    boxes[t] = {cell_of(l.x, lo.x, extent.x), cell_of(l.y, lo.y, extent.y),
                cell_of(h.x, lo.x, extent.x), cell_of(h.y, lo.y, extent.y)};
    for (int y = boxes[t].y; y <= boxes[t].w; ++y)
      for (int x = boxes[t].x; x <= boxes[t].z; ++x)
        cells[size_t(y) * size_t(side) + size_t(x)].push_back(uint32_t(t));
  }
  std::vector<uint8_t> overlapping(nt, 0);
  auto corners = [&](uint32_t t, dvec2 (&out)[3]) {
    for (int k = 0; k < 3; ++k) out[k] = dvec2(mesh.lightmap_uvs[mesh.triangles[t][k]]);
  };
  for (size_t cell = 0; cell < cells.size(); ++cell) {
    const std::vector<uint32_t>& list = cells[cell];
    const int cx = int(cell % size_t(side)), cy = int(cell / size_t(side));
    for (size_t i = 0; i < list.size(); ++i)
      for (size_t j = i + 1; j < list.size(); ++j) {
        const uint32_t s = list[i], t = list[j];
        if (check.island[s] != check.island[t]) continue;
        // Each pair once: in the first cell both boxes share.
        if (std::max(boxes[s].x, boxes[t].x) != cx || std::max(boxes[s].y, boxes[t].y) != cy)
          continue;
        dvec2 p[3], q[3];
        corners(s, p), corners(t, q);
        if (interiors_overlap(p, q, eps)) overlapping[s] = overlapping[t] = 1;
      }
  }
  for (uint8_t o : overlapping) check.overlapping += o;
  return check;
}

}  // namespace lb
