#include "bake/illumination/atlas_unfold.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace lb {

namespace {

// A strip's rectangle stays at least this full (chart area / bounding rectangle in the seed's
// frame), so growth follows strips and stops where a shape would waste its rectangle. Below
// one half, because a strip of quads grows a triangle at a time and a lone triangle fills half
// of its rectangle.
constexpr double kMinFill = 0.4;
// Overlap tests are linear in the chart, so a chart stops growing at this many triangles.
constexpr size_t kMaxUnfoldTriangles = 2048;

using Tri2 = std::array<vec2, 3>;

// True if the interiors of two triangles overlap by more than eps (separating axes: the six
// edge normals). Triangles that only touch along an edge or at a corner do not overlap.
bool overlap(const Tri2& a, const Tri2& b, float eps) {
  for (const Tri2* t : {&a, &b})
    for (int k = 0; k < 3; ++k) {
      const vec2 e = (*t)[(k + 1) % 3] - (*t)[k];
      const vec2 n(-e.y, e.x);
      const float length = glm::length(n);
      if (!(length > 0.0f)) continue;
      float a_lo = 1e30f, a_hi = -1e30f, b_lo = 1e30f, b_hi = -1e30f;
      for (int j = 0; j < 3; ++j) {
        const float pa = glm::dot(a[j], n) / length, pb = glm::dot(b[j], n) / length;
        a_lo = std::min(a_lo, pa), a_hi = std::max(a_hi, pa);
        b_lo = std::min(b_lo, pb), b_hi = std::max(b_hi, pb);
      }
      if (a_hi <= b_lo + eps || b_hi <= a_lo + eps) return false;
    }
  return true;
}

// The seed lies with its shortest edge along x, so a strip of rectangles across or along that
// edge runs along an axis of the frame the fill is measured in.
Tri2 place_seed(const Mesh& mesh, uint32_t t) {
  const uvec3 tri = mesh.triangles[t];
  const vec3 p[3] = {mesh.positions[tri.x], mesh.positions[tri.y], mesh.positions[tri.z]};
  int k0 = 0;
  float shortest = 1e30f;
  for (int k = 0; k < 3; ++k) {
    const float length = glm::length(p[(k + 1) % 3] - p[k]);
    if (length < shortest) shortest = length, k0 = k;
  }
  const int k1 = (k0 + 1) % 3, k2 = (k0 + 2) % 3;
  const vec3 e = p[k1] - p[k0], d = p[k2] - p[k0];
  const float along = glm::dot(d, e) / shortest;
  const float perp = glm::length(glm::cross(d, e)) / shortest;
  Tri2 q;
  q[size_t(k0)] = vec2(0.0f);
  q[size_t(k1)] = vec2(shortest, 0.0f);
  q[size_t(k2)] = vec2(along, perp);
  return q;
}

// Places triangle `next` across the edge it shares with the placed triangle `from` (corners
// `q`), on the other side of that edge: a rotation about the edge into the chart's plane.
// Returns false if the two do not share two corner positions.
bool place_across(const Mesh& mesh, uint32_t from, const Tri2& q, uint32_t next, Tri2& out) {
  const uvec3 a = mesh.triangles[from], b = mesh.triangles[next];
  int shared_a[2], shared_b[2], count = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (count < 2 && mesh.positions[a[i]] == mesh.positions[b[j]]) {
        shared_a[count] = i, shared_b[count] = j;
        ++count;
      }
  if (count != 2) return false;
  const int third_a = 3 - shared_a[0] - shared_a[1], third_b = 3 - shared_b[0] - shared_b[1];
  const vec3 e0 = mesh.positions[b[shared_b[0]]], e1 = mesh.positions[b[shared_b[1]]];
  const vec3 c = mesh.positions[b[third_b]];
  const float world_length = glm::length(e1 - e0);
  const vec2 u2 = q[size_t(shared_a[1])] - q[size_t(shared_a[0])];
  const float plane_length = glm::length(u2);
  if (!(world_length > 0.0f) || !(plane_length > 0.0f)) return false;
  const vec2 u = u2 / plane_length;
  vec2 n(-u.y, u.x);
  if (glm::dot(q[size_t(third_a)] - q[size_t(shared_a[0])], n) > 0.0f) n = -n;
  const float along = glm::dot(c - e0, e1 - e0) / world_length;
  const float perp = glm::length(glm::cross(c - e0, e1 - e0)) / world_length;
  out[size_t(shared_b[0])] = q[size_t(shared_a[0])];
  out[size_t(shared_b[1])] = q[size_t(shared_a[1])];
  out[size_t(third_b)] = q[size_t(shared_a[0])] + along * u + perp * n;
  return true;
}

double area_2d(const Tri2& q) {
  const vec2 e1 = q[1] - q[0], e2 = q[2] - q[0];
  return 0.5 * std::abs(double(e1.x) * e2.y - double(e1.y) * e2.x);
}

}  // namespace

int unfold_charts(const Mesh& mesh, const std::vector<std::vector<uint32_t>>& neighbours,
                  const std::vector<uint32_t>& seeds, float texel, std::vector<int>& chart_of,
                  int chart_count, std::vector<std::array<vec2, 3>>& corners,
                  std::vector<uint8_t>& unfolded) {
  const size_t nt = mesh.triangles.size();
  corners.assign(nt, Tri2{});
  unfolded.assign(size_t(chart_count), 0);
  std::vector<uint8_t> pooled(nt, 0);
  for (uint32_t t : seeds) pooled[t] = 1;
  const float eps = 1e-4f * texel;
  std::vector<uint32_t> members;
  struct Edge {
    uint32_t from, to;
  };
  std::vector<Edge> frontier;
  for (const uint32_t seed : seeds) {
    if (!pooled[seed]) continue;
    const int id = chart_count++;
    unfolded.push_back(1);
    pooled[seed] = 0;
    chart_of[seed] = id;
    corners[seed] = place_seed(mesh, seed);
    members.assign(1, uint32_t(seed));
    double area = area_2d(corners[seed]);
    vec2 lo = glm::min(corners[seed][0], glm::min(corners[seed][1], corners[seed][2]));
    vec2 hi = glm::max(corners[seed][0], glm::max(corners[seed][1], corners[seed][2]));
    frontier.clear();
    for (uint32_t nb : neighbours[seed]) frontier.push_back({seed, nb});
    // Greedy: the candidate that grows the chart's rectangle least joins first (the first one
    // in frontier order on ties), so a strip fills its rectangle before it lengthens, and the
    // last face of a ring joins whole at one end instead of a triangle at each.
    while (!frontier.empty() && members.size() < kMaxUnfoldTriangles) {
      size_t best = 0;
      bool found = false;
      double best_growth = 0.0;
      Tri2 best_q{};
      for (size_t i = 0; i < frontier.size();) {
        Tri2 q;
        if (!pooled[frontier[i].to] ||
            !place_across(mesh, frontier[i].from, corners[frontier[i].from], frontier[i].to, q)) {
          frontier.erase(frontier.begin() + std::ptrdiff_t(i));
          continue;
        }
        const vec2 new_lo = glm::min(lo, glm::min(q[0], glm::min(q[1], q[2])));
        const vec2 new_hi = glm::max(hi, glm::max(q[0], glm::max(q[1], q[2])));
        const double growth = double(new_hi.x - new_lo.x) * double(new_hi.y - new_lo.y) -
                              double(hi.x - lo.x) * double(hi.y - lo.y);
        if (!found || growth < best_growth) best = i, best_growth = growth, best_q = q;
        found = true;
        ++i;
      }
      if (!found) break;
      const uint32_t nb = frontier[best].to;
      frontier.erase(frontier.begin() + std::ptrdiff_t(best));
      const Tri2& q = best_q;
      const vec2 q_lo = glm::min(q[0], glm::min(q[1], q[2]));
      const vec2 q_hi = glm::max(q[0], glm::max(q[1], q[2]));
      const vec2 new_lo = glm::min(lo, q_lo), new_hi = glm::max(hi, q_hi);
      const double new_area = area + area_2d(q);
      const vec2 extent = new_hi - new_lo;
      if (new_area < kMinFill * double(extent.x) * double(extent.y)) continue;
      bool clear = true;
      for (uint32_t m : members) {
        const Tri2& r = corners[m];
        const vec2 r_lo = glm::min(r[0], glm::min(r[1], r[2]));
        const vec2 r_hi = glm::max(r[0], glm::max(r[1], r[2]));
        if (r_hi.x <= q_lo.x + eps || q_hi.x <= r_lo.x + eps || r_hi.y <= q_lo.y + eps ||
            q_hi.y <= r_lo.y + eps)
          continue;
        if (overlap(q, r, eps)) {
          clear = false;
          break;
        }
      }
      if (!clear) continue;
      pooled[nb] = 0;
      chart_of[nb] = id;
      corners[nb] = q;
      members.push_back(nb);
      area = new_area;
      lo = new_lo, hi = new_hi;
      for (uint32_t next : neighbours[nb])
        if (pooled[next]) frontier.push_back({nb, next});
    }
  }
  return chart_count;
}

}  // namespace lb
