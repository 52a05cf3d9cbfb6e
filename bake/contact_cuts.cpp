#include "bake/contact_cuts.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <map>
#include <optional>
#include <tuple>
#include <unordered_map>

#include "bake/sampling.h"

namespace lb {

namespace {

using glm::dvec3;

struct Plane {
  dvec3 normal;   // unit
  double offset;  // dot(normal, x) = offset
  double distance(vec3 p) const { return glm::dot(normal, dvec3(p)) - offset; }
};

// A triangle of another mesh that may cut: its plane, corners and bounds.
struct Cutter {
  uint32_t plane;  // global plane id (deduplicated)
  uint32_t mesh;   // scene mesh
  dvec3 corner[3];
  vec3 low, high;
};

// A cutter hovering over a receiver: every corner in front of the receiver's plane, no farther
// than the gap, and facing along or against it (the lamp under a ceiling, a cloth on a table).
constexpr double kHoverCos = 0.9;  // 26 degrees
// Each plane cuts across every piece it meets, so k planes make ~k^2 / 2 pieces: a dense curved
// mesh through a wall (a 20k-triangle ball through a block) made 1.7 M triangles and 3 minutes
// of loading, a 2 M-triangle one ran out of memory. Beyond this many planes a receiving
// triangle takes an evenly spread subset (cutters come in mesh order, so neighbours along
// the contact line): at most ~300 pieces, the line followed by a polygon of 24 sides.
constexpr size_t kMaxCutPlanesPerTriangle = 24;

bool hovers(const dvec3 (&corner)[3], dvec3 normal, const Plane& receiver, double tolerance,
            double gap) {
  if (std::abs(glm::dot(normal, receiver.normal)) < kHoverCos) return false;
  for (const dvec3& q : corner) {
    const double s = glm::dot(receiver.normal, q) - receiver.offset;
    if (!(s > tolerance && s <= gap)) return false;
  }
  return true;
}

// Does the section of triangle (p0, p1, p2) by a plane through segment [a, b] reach the
// segment's extent along it (within `tolerance`)? `s`, the corners' distances, straddle it.
bool section_within_segment(const vec3 p[3], const double s[3], dvec3 a, dvec3 b,
                            double tolerance) {
  const dvec3 along = glm::normalize(b - a);
  const double length = glm::dot(b - a, along);
  double low = 1e300, high = -1e300;
  for (int k = 0; k < 3; ++k) {
    const int j = (k + 1) % 3;
    const auto add = [&](dvec3 q) {
      const double t = glm::dot(q - a, along);
      low = std::min(low, t), high = std::max(high, t);
    };
    if (std::abs(s[k]) <= tolerance) add(dvec3(p[k]));
    if ((s[k] > tolerance && s[j] < -tolerance) || (s[k] < -tolerance && s[j] > tolerance))
      add(dvec3(p[k]) + s[k] / (s[k] - s[j]) * (dvec3(p[j]) - dvec3(p[k])));
  }
  return high >= -tolerance && low <= length + tolerance;
}

// Planes deduplicated by quantised normal and offset, so the two triangles of a box face (or
// coplanar faces of different meshes) share one id and cut a shared edge at one vertex.
class PlaneSet {
 public:
  explicit PlaneSet(double tolerance) : tolerance_(tolerance) {}
  uint32_t add(const Plane& plane) {
    const auto q = [](double x, double step) { return int64_t(std::llround(x / step)); };
    const auto key = std::make_tuple(q(plane.normal.x, 1e-6), q(plane.normal.y, 1e-6),
                                     q(plane.normal.z, 1e-6), q(plane.offset, tolerance_));
    const auto [it, inserted] = ids_.try_emplace(key, uint32_t(planes.size()));
    if (inserted) planes.push_back(plane);
    return it->second;
  }
  std::vector<Plane> planes;

 private:
  double tolerance_;
  std::map<std::tuple<int64_t, int64_t, int64_t, int64_t>, uint32_t> ids_;
};

// Appends the point of edge (a, b) at fraction t from the lower index; every attribute linear.
uint32_t append_lerp(Mesh& mesh, uint32_t lo, uint32_t hi, float t) {
  auto lerp = [t](auto x, auto y) { return x + (y - x) * t; };
  auto unit = [](vec3 v, vec3 fallback) {
    const float length = glm::length(v);
    return length > 0.0f ? v / length : fallback;
  };
  mesh.positions.push_back(lerp(mesh.positions[lo], mesh.positions[hi]));
  if (!mesh.normals.empty())
    mesh.normals.push_back(unit(lerp(mesh.normals[lo], mesh.normals[hi]), mesh.normals[lo]));
  if (!mesh.uvs.empty()) mesh.uvs.push_back(lerp(mesh.uvs[lo], mesh.uvs[hi]));
  if (!mesh.lightmap_uvs.empty())
    mesh.lightmap_uvs.push_back(lerp(mesh.lightmap_uvs[lo], mesh.lightmap_uvs[hi]));
  if (!mesh.tangents.empty()) {
    const vec4 a = mesh.tangents[lo], b = mesh.tangents[hi];
    mesh.tangents.push_back(vec4(unit(lerp(vec3(a), vec3(b)), vec3(a)), a.w));
  }
  return uint32_t(mesh.positions.size() - 1);
}

// Appends the centroid of `tri`; every attribute the mean of the corners'.
uint32_t append_centroid(Mesh& mesh, uvec3 tri) {
  auto mean = [&](const auto& a) { return (a[tri.x] + a[tri.y] + a[tri.z]) / 3.0f; };
  auto unit = [](vec3 v) {
    const float length = glm::length(v);
    return length > 0.0f ? v / length : vec3(0.0f, 0.0f, 1.0f);
  };
  mesh.positions.push_back(mean(mesh.positions));
  if (!mesh.normals.empty()) mesh.normals.push_back(unit(mean(mesh.normals)));
  if (!mesh.uvs.empty()) mesh.uvs.push_back(mean(mesh.uvs));
  if (!mesh.lightmap_uvs.empty()) mesh.lightmap_uvs.push_back(mean(mesh.lightmap_uvs));
  if (!mesh.tangents.empty()) {
    const vec4 t = mesh.tangents[tri.x];
    mesh.tangents.push_back(vec4(unit(vec3(mean(mesh.tangents))), t.w));
  }
  return uint32_t(mesh.positions.size() - 1);
}

// Does the section of triangle (p0, p1, p2) by the cutter's plane meet the cutter (all within
// `tolerance`)? `s` are the corners' signed distances, known to straddle the plane.
bool section_meets(const vec3 p[3], const double s[3], const Cutter& cutter, const Plane& plane,
                   double tolerance) {
  // End points of the section: where the edges cross, and corners on the plane.
  dvec3 ends[3];
  int count = 0;
  for (int k = 0; k < 3 && count < 3; ++k) {
    const int j = (k + 1) % 3;
    if (std::abs(s[k]) <= tolerance) ends[count++] = dvec3(p[k]);
    if ((s[k] > tolerance && s[j] < -tolerance) || (s[k] < -tolerance && s[j] > tolerance)) {
      const double t = s[k] / (s[k] - s[j]);
      ends[count++] = dvec3(p[k]) + t * (dvec3(p[j]) - dvec3(p[k]));
    }
  }
  if (count < 2) return false;
  const dvec3 a = ends[0], d = ends[1] - ends[0];
  // Clip [a, a + d] against the cutter's edges (inward half-planes, widened by the tolerance).
  double low = 0.0, high = 1.0;
  for (int k = 0; k < 3; ++k) {
    const dvec3 edge = cutter.corner[(k + 1) % 3] - cutter.corner[k];
    dvec3 inward = glm::cross(plane.normal, edge);
    const double length = glm::length(inward);
    if (!(length > 0.0)) return false;
    inward /= length;
    const double at = glm::dot(inward, a - cutter.corner[k]) + tolerance;
    const double rate = glm::dot(inward, d);
    if (std::abs(rate) < 1e-300) {
      if (at < 0.0) return false;
      continue;
    }
    const double t = -at / rate;
    if (rate > 0.0)
      low = std::max(low, t);
    else
      high = std::min(high, t);
    if (low > high) return false;
  }
  return true;
}

// Where a contact line ends inside a triangle, its neighbour across the cut edge was not cut:
// that neighbour gets the cut vertices on its edge (a centroid fan keeps it conforming, so
// the surface stays crack-free and patches can grow across).
template <class Canonical, class EdgeSupport>
void resolve_t_junctions(Mesh& out, uint32_t original_count, const std::vector<uint64_t>& support,
                         Canonical& canonical, EdgeSupport& edge_support) {
  constexpr uint64_t kNone = ~uint64_t(0);
  // Support edges by position (both sides of a seam alike) -> the cut vertices on them.
  auto position_key = [&](uint64_t edge) {
    return uint64_t(canonical(uint32_t(edge >> 32))) << 32 | canonical(uint32_t(edge));
  };
  std::unordered_map<uint64_t, std::vector<uint32_t>> on_edge;
  for (size_t i = 0; i < support.size(); ++i)
    if (support[i] != kNone)
      on_edge[position_key(support[i])].push_back(original_count + uint32_t(i));
  if (on_edge.empty()) return;
  auto param = [&](uint64_t edge, vec3 p) {
    const dvec3 a(out.positions[edge >> 32]), b(out.positions[uint32_t(edge)]);
    return glm::dot(dvec3(p) - a, b - a) / glm::dot(b - a, b - a);
  };
  const size_t triangle_count = out.triangles.size();
  std::vector<uvec3> kept;
  kept.reserve(triangle_count);
  std::vector<uint32_t> polygon;
  std::vector<std::pair<double, uint32_t>> inserts;
  for (size_t t = 0; t < triangle_count; ++t) {
    const uvec3 tri = out.triangles[t];
    polygon.clear();
    bool changed = false;
    for (int k = 0; k < 3; ++k) {
      const uint32_t u = tri[k], v = tri[(k + 1) % 3];
      polygon.push_back(u);
      const uint64_t edge = edge_support(u, v);
      if (edge == kNone) continue;
      const auto found = on_edge.find(position_key(edge));
      if (found == on_edge.end()) continue;
      const double tu = param(edge, out.positions[u]), tv = param(edge, out.positions[v]);
      inserts.clear();
      for (uint32_t c : found->second) {
        if (canonical(c) == canonical(u) || canonical(c) == canonical(v)) continue;
        const double tc = param(edge, out.positions[c]);
        if ((tc - tu) * (tc - tv) < 0.0) inserts.emplace_back(std::abs(tc - tu), c);
      }
      std::sort(inserts.begin(), inserts.end());
      for (const auto& [distance, c] : inserts) {
        changed = true;
        if (support[c - original_count] == edge) {  // cut on this very edge: share it
          polygon.push_back(c);
          continue;
        }
        // Across a seam: the same position with this side's attributes.
        const float f = float(distance / std::abs(tv - tu));
        const uint32_t copy = append_lerp(out, u, v, f);
        out.positions[copy] = out.positions[c];
        polygon.push_back(copy);
      }
    }
    if (!changed) {
      kept.push_back(tri);
      continue;
    }
    // Centroid fan: every piece keeps the triangle's orientation and none is degenerate.
    const uint32_t centre = append_centroid(out, tri);
    for (size_t k = 0; k < polygon.size(); ++k)
      kept.push_back(uvec3(centre, polygon[k], polygon[(k + 1) % polygon.size()]));
  }
  out.triangles.swap(kept);
}

// The larger side of the bounding box, in the plane's own axes, of what `mesh` hides of
// `plane`: its section (corners within `tolerance` of the plane, and where edges cross it)
// when an edge crosses the plane or a triangle lies in it; 0 when the mesh only touches the
// plane at vertices or along edges (a torus or a ball resting on it hides nothing).
double section_extent(const Mesh& mesh, const Plane& plane, double tolerance) {
  const dvec3 n = plane.normal;
  const dvec3 u = glm::normalize(std::abs(n.x) < 0.5 ? glm::cross(n, dvec3(1, 0, 0))
                                                     : glm::cross(n, dvec3(0, 1, 0)));
  const dvec3 v = glm::cross(n, u);
  glm::dvec2 low(1e300), high(-1e300);
  bool hides = false;
  auto add = [&](dvec3 p) {
    const glm::dvec2 q(glm::dot(u, p), glm::dot(v, p));
    low = glm::min(low, q), high = glm::max(high, q);
  };
  for (const uvec3& tri : mesh.triangles) {
    double s[3];
    for (int k = 0; k < 3; ++k) s[k] = plane.distance(mesh.positions[tri[k]]);
    hides = hides || (std::abs(s[0]) <= tolerance && std::abs(s[1]) <= tolerance &&
                      std::abs(s[2]) <= tolerance);
    for (int k = 0; k < 3; ++k) {
      const int j = (k + 1) % 3;
      const dvec3 a(mesh.positions[tri[k]]), b(mesh.positions[tri[j]]);
      if (std::abs(s[k]) <= tolerance) add(a);
      if ((s[k] > tolerance && s[j] < -tolerance) || (s[k] < -tolerance && s[j] > tolerance)) {
        add(a + s[k] / (s[k] - s[j]) * (b - a));
        hides = true;
      }
    }
  }
  return hides ? std::max(high.x - low.x, high.y - low.y) : 0.0;
}

// The larger side of the bounding box, in the receiver plane's axes, of the triangles of `mesh`
// that hover over `receiver` (`hovers`): what a lamp or a cloth hides of it.
double hover_extent(const Mesh& mesh, const Plane& receiver, double tolerance, double gap) {
  const dvec3 n = receiver.normal;
  const dvec3 u = glm::normalize(std::abs(n.x) < 0.5 ? glm::cross(n, dvec3(1, 0, 0))
                                                     : glm::cross(n, dvec3(0, 1, 0)));
  const dvec3 v = glm::cross(n, u);
  glm::dvec2 low(1e300), high(-1e300);
  for (const uvec3& tri : mesh.triangles) {
    dvec3 corner[3];
    for (int k = 0; k < 3; ++k) corner[k] = dvec3(mesh.positions[tri[k]]);
    const dvec3 normal = glm::cross(corner[1] - corner[0], corner[2] - corner[0]);
    const double length = glm::length(normal);
    if (!(length > 0.0) || !hovers(corner, normal / length, receiver, tolerance, gap)) continue;
    for (const dvec3& q : corner) {
      const glm::dvec2 p(glm::dot(u, q), glm::dot(v, q));
      low = glm::min(low, p), high = glm::max(high, p);
    }
  }
  return high.x >= low.x ? std::max(high.x - low.x, high.y - low.y) : 0.0;
}

// An edge as its ends' position bits, in order: the key the triangles on it share.
using EdgeKey = std::array<uint32_t, 6>;

EdgeKey edge_key(dvec3 a, dvec3 b) {
  const auto bits = [](dvec3 p) {
    const vec3 q = vec3(p) + vec3(0.0f);  // -0 is +0
    std::array<uint32_t, 3> out;
    std::memcpy(out.data(), &q, sizeof out);
    return out;
  };
  std::array<uint32_t, 3> x = bits(a), y = bits(b);
  if (y < x) std::swap(x, y);
  return {x[0], x[1], x[2], y[0], y[1], y[2]};
}

struct EdgeKeyHash {
  size_t operator()(const EdgeKey& key) const {
    uint64_t h = 1469598103934665603ull;
    for (const uint32_t v : key) h = (h ^ v) * 1099511628211ull;
    return size_t(h);
  }
};

}  // namespace

float contact_tolerance(const Scene& scene) {
  const Bounds bounds = scene_bounds(scene);
  if (bounds.empty()) return 1e-6f;
  const vec3 e = bounds.extent();
  return std::max(1e-6f * std::max({e.x, e.y, e.z}), 1e-7f);
}

BoxGrid mesh_box_grid(const Scene& scene) {
  std::vector<vec3> low(scene.meshes.size(), vec3(1e30f)), high(scene.meshes.size(), vec3(-1e30f));
  for (size_t m = 0; m < scene.meshes.size(); ++m)
    for (const vec3& p : scene.meshes[m].positions)
      low[m] = glm::min(low[m], p), high[m] = glm::max(high[m], p);
  return BoxGrid(std::move(low), std::move(high));
}

Mesh cut_along_contacts(const Mesh& mesh, const Scene& scene, const BoxGrid& meshes, size_t self,
                        float tolerance, float min_footprint, float hover_gap) {
  const double tol = tolerance;
  const float reach = std::max(tolerance, hover_gap);
  // Bounds of the receiving mesh, to keep only cutters that can reach it.
  vec3 low(1e30f), high(-1e30f);
  for (const vec3& p : mesh.positions) low = glm::min(low, p), high = glm::max(high, p);
  low -= vec3(reach), high += vec3(reach);

  // Only meshes whose bounds meet the receiver's hold a triangle that can (every triangle's
  // bounds lie in its mesh's); ascending, so the plane ids are those of a scan of all meshes.
  std::vector<uint32_t> near;
  meshes.overlapping(low, high, near);
  PlaneSet planes(tol);
  std::vector<Cutter> cutters;
  std::unordered_map<uint32_t, std::pair<size_t, size_t>> cutters_of_mesh;  // [begin, end)
  for (const uint32_t m : near) {
    if (m == self) continue;
    cutters_of_mesh[m].first = cutters.size();
    const Mesh& other = scene.meshes[m];
    for (size_t t = 0; t < other.triangles.size(); ++t) {
      Cutter c;
      c.low = vec3(1e30f), c.high = vec3(-1e30f);
      for (int k = 0; k < 3; ++k) {
        const vec3 p = other.positions[other.triangles[t][k]];
        c.corner[k] = dvec3(p);
        c.low = glm::min(c.low, p), c.high = glm::max(c.high, p);
      }
      if (glm::any(glm::lessThan(c.high, low)) || glm::any(glm::greaterThan(c.low, high))) continue;
      const dvec3 n = glm::cross(c.corner[1] - c.corner[0], c.corner[2] - c.corner[0]);
      const double length = glm::length(n);
      if (!(length > 0.0)) continue;
      const Plane plane{n / length, glm::dot(n / length, c.corner[0])};
      c.plane = planes.add(plane);
      c.mesh = m;
      cutters.push_back(c);
    }
    cutters_of_mesh[m].second = cutters.size();
  }
  if (cutters.empty()) return mesh;

  // A hovering cutter's outline edges (bit k: edge k -> k + 1): those no other triangle of its
  // mesh facing the same way shares (a lamp quad's four sides, not its diagonal; a slab's
  // bottom rim). Found on first use, one edge table a mesh.
  std::unordered_map<uint32_t, std::unordered_map<EdgeKey, std::vector<uint32_t>, EdgeKeyHash>>
      edges_of_mesh;
  std::vector<uint8_t> outline(cutters.size(), 0xff);
  auto outline_of = [&](uint32_t i) {
    if (outline[i] != 0xff) return outline[i];
    const Cutter& c = cutters[i];
    auto& edges = edges_of_mesh[c.mesh];
    if (edges.empty()) {
      const auto [begin, end] = cutters_of_mesh[c.mesh];
      for (size_t j = begin; j < end; ++j)
        for (int k = 0; k < 3; ++k)
          edges[edge_key(cutters[j].corner[k], cutters[j].corner[(k + 1) % 3])].push_back(
              uint32_t(j));
    }
    const dvec3 n = planes.planes[c.plane].normal;
    uint8_t bits = 0;
    for (int k = 0; k < 3; ++k) {
      bool shared = false;
      for (const uint32_t j : edges[edge_key(c.corner[k], c.corner[(k + 1) % 3])])
        shared = shared ||
                 (j != i && glm::dot(planes.planes[cutters[j].plane].normal, n) >= kHoverCos);
      bits |= shared ? 0 : uint8_t(1u << k);
    }
    return outline[i] = bits;
  };

  Mesh out = mesh;
  out.triangles.clear();
  out.hidden.clear();
  out.triangles.reserve(mesh.triangles.size());
  // Edge (lo, hi) -> (plane, vertex) of its cuts, so that neighbours share the vertex.
  std::unordered_map<uint64_t, std::vector<std::pair<uint32_t, uint32_t>>> split_cache;
  const uint32_t original_count = uint32_t(mesh.positions.size());
  // Coincident vertices (seams) share a canonical id; edges are ordered by it, so both sides
  // of a seam compute a cut at the same bits.
  std::map<std::tuple<float, float, float>, uint32_t> position_ids;
  std::vector<uint32_t> canon;
  auto canonical = [&](uint32_t v) {
    if (v >= canon.size()) canon.resize(out.positions.size(), ~0u);
    if (canon[v] == ~0u) {
      const vec3 q = out.positions[v] + vec3(0.0f);  // -0 is +0
      canon[v] =
          position_ids.try_emplace({q.x, q.y, q.z}, uint32_t(position_ids.size())).first->second;
    }
    return canon[v];
  };
  // Per cut vertex (index - original_count): the original edge it lies on, as original
  // vertex indices (a, b) in canonical order, or none (inside a triangle).
  constexpr uint64_t kNone = ~uint64_t(0);
  std::vector<uint64_t> support;
  auto support_of = [&](uint32_t v) -> uint64_t {
    return v < original_count ? kNone : support[v - original_count];
  };
  auto on_support = [&](uint32_t v, uint64_t edge) {  // v an end of, or cut on, `edge`
    if (v < original_count)
      return canonical(v) == canonical(uint32_t(edge >> 32)) ||
             canonical(v) == canonical(uint32_t(edge));
    return support_of(v) == edge;
  };
  auto edge_support = [&](uint32_t a, uint32_t b) -> uint64_t {
    if (a < original_count && b < original_count) {
      if (canonical(a) > canonical(b)) std::swap(a, b);
      return uint64_t(a) << 32 | b;
    }
    for (const uint64_t edge : {support_of(a), support_of(b)})
      if (edge != kNone && on_support(a, edge) && on_support(b, edge)) return edge;
    return kNone;
  };
  std::vector<vec3> cutter_low(cutters.size()), cutter_high(cutters.size());
  for (size_t i = 0; i < cutters.size(); ++i)
    cutter_low[i] = cutters[i].low, cutter_high[i] = cutters[i].high;
  const BoxGrid cutter_grid(std::move(cutter_low), std::move(cutter_high));
  // Does cutter mesh m cut receiving plane r (its footprint on r reaches min_footprint)?
  // Decided per plane, not per triangle, so coplanar neighbours agree.
  PlaneSet receiver_planes(tol);
  std::unordered_map<uint64_t, bool> cuts_plane, hover_cuts_plane;
  auto footprint_cuts = [&](uint32_t m, uint32_t r) {
    const auto [it, inserted] = cuts_plane.try_emplace(uint64_t(m) << 32 | r, true);
    if (inserted)
      it->second = section_extent(scene.meshes[m], receiver_planes.planes[r], tol) >= min_footprint;
    return it->second;
  };
  auto hover_cuts = [&](uint32_t m, uint32_t r) {
    const auto [it, inserted] = hover_cuts_plane.try_emplace(uint64_t(m) << 32 | r, true);
    if (inserted)
      it->second = hover_extent(scene.meshes[m], receiver_planes.planes[r], tol, hover_gap) >=
                   min_footprint;
    return it->second;
  };
  std::vector<uint32_t> cuts, candidates;
  std::vector<uvec3> pieces, next;
  for (const uvec3& tri : mesh.triangles) {
    const vec3 p[3] = {mesh.positions[tri.x], mesh.positions[tri.y], mesh.positions[tri.z]};
    uint32_t receiver = ~0u;  // plane id, found when a cutter straddles or hovers
    bool degenerate = false;
    auto receiver_plane = [&]() {
      if (receiver == ~0u && !degenerate) {
        const dvec3 n = glm::cross(dvec3(p[1] - p[0]), dvec3(p[2] - p[0]));
        const double length = glm::length(n);
        degenerate = !(length > 0.0);
        if (!degenerate)
          receiver = receiver_planes.add({n / length, glm::dot(n / length, dvec3(p[0]))});
      }
      return receiver;
    };
    const vec3 t_low = glm::min(p[0], glm::min(p[1], p[2])) - vec3(reach);
    const vec3 t_high = glm::max(p[0], glm::max(p[1], p[2])) + vec3(reach);
    cuts.clear();
    cutter_grid.overlapping(t_low, t_high, candidates);
    for (const uint32_t i : candidates) {
      const Cutter& c = cutters[i];
      const Plane plane = planes.planes[c.plane];  // a copy: the outline adds planes below
      const double s[3] = {plane.distance(p[0]), plane.distance(p[1]), plane.distance(p[2])};
      const bool above = s[0] > tol || s[1] > tol || s[2] > tol;
      const bool below = s[0] < -tol || s[1] < -tol || s[2] < -tol;
      if (above && below && section_meets(p, s, c, plane, tol)) {
        if (min_footprint > 0.0f) {
          if (receiver_plane() == ~0u) break;  // degenerate: nothing to cut
          if (!footprint_cuts(c.mesh, receiver)) continue;
        }
        cuts.push_back(c.plane);
        continue;
      }
      // Hovering within the gap: cut along the outline's edges, each by the plane through it
      // across the cutter's own plane (the same plane for every receiving triangle).
      if (!(hover_gap > 0.0f) || receiver_plane() == ~0u) continue;
      const Plane& receiving = receiver_planes.planes[receiver];
      if (!hovers(c.corner, plane.normal, receiving, tol, hover_gap)) continue;
      if (min_footprint > 0.0f && !hover_cuts(c.mesh, receiver)) continue;
      const uint8_t bits = outline_of(i);
      for (int k = 0; k < 3; ++k) {
        if (!(bits & (1u << k))) continue;
        const dvec3 a = c.corner[k], b = c.corner[(k + 1) % 3];
        // A curved outline (a ring's rim, a glass's foot) has short edges, each of whose
        // planes would cut across whole receiving triangles: it cuts nothing, as a small
        // cutter does not.
        if (glm::length(b - a) < double(min_footprint)) continue;
        const dvec3 normal = glm::cross(b - a, plane.normal);
        const double length = glm::length(normal);
        if (!(length > 0.0)) continue;
        const Plane side{normal / length, glm::dot(normal / length, a)};
        const double d[3] = {side.distance(p[0]), side.distance(p[1]), side.distance(p[2])};
        const bool front = d[0] > tol || d[1] > tol || d[2] > tol;
        const bool back = d[0] < -tol || d[1] < -tol || d[2] < -tol;
        if (!front || !back) continue;
        if (section_within_segment(p, d, a, b, tol)) cuts.push_back(planes.add(side));
      }
    }
    if (cuts.empty()) {
      out.triangles.push_back(tri);
      continue;
    }
    std::sort(cuts.begin(), cuts.end());
    cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
    if (cuts.size() > kMaxCutPlanesPerTriangle) {
      for (size_t k = 0; k < kMaxCutPlanesPerTriangle; ++k)
        cuts[k] = cuts[k * cuts.size() / kMaxCutPlanesPerTriangle];
      cuts.resize(kMaxCutPlanesPerTriangle);
    }
    pieces.assign(1, tri);
    for (uint32_t id : cuts) {
      const Plane& plane = planes.planes[id];
      next.clear();
      for (const uvec3& piece : pieces) {
        double s[3];
        int sign[3];
        for (int k = 0; k < 3; ++k) {
          s[k] = plane.distance(out.positions[piece[k]]);
          sign[k] = s[k] > tol ? 1 : (s[k] < -tol ? -1 : 0);
        }
        const bool straddles = (sign[0] > 0 || sign[1] > 0 || sign[2] > 0) &&
                               (sign[0] < 0 || sign[1] < 0 || sign[2] < 0);
        if (!straddles) {
          next.push_back(piece);
          continue;
        }
        // Walk the corners; insert the crossing vertex on each edge that changes side; then
        // fan each side's convex polygon (corners on the plane belong to both).
        uint32_t positive[4], negative[4];
        int np = 0, nn = 0;
        for (int k = 0; k < 3; ++k) {
          const int j = (k + 1) % 3;
          if (sign[k] >= 0) positive[np++] = piece[k];
          if (sign[k] <= 0) negative[nn++] = piece[k];
          if (sign[k] * sign[j] < 0) {
            uint32_t lo = piece[k], hi = piece[j];
            if (canonical(lo) > canonical(hi)) std::swap(lo, hi);
            auto& known = split_cache[uint64_t(lo) << 32 | hi];
            uint32_t v = ~0u;
            for (const auto& [plane_id, vertex] : known)
              if (plane_id == id) v = vertex;
            if (v == ~0u) {
              const double s_lo = plane.distance(out.positions[lo]);
              const double s_hi = plane.distance(out.positions[hi]);
              const uint64_t edge = edge_support(lo, hi);
              v = append_lerp(out, lo, hi, float(s_lo / (s_lo - s_hi)));
              support.push_back(edge);
              known.emplace_back(id, v);
            }
            positive[np++] = v;
            negative[nn++] = v;
          }
        }
        for (int k = 1; k + 1 < np; ++k)
          next.push_back(uvec3(positive[0], positive[k], positive[k + 1]));
        for (int k = 1; k + 1 < nn; ++k)
          next.push_back(uvec3(negative[0], negative[k], negative[k + 1]));
      }
      pieces.swap(next);
    }
    out.triangles.insert(out.triangles.end(), pieces.begin(), pieces.end());
  }
  resolve_t_junctions(out, original_count, support, canonical, edge_support);
  return out;
}

namespace {

// A triangle is covered when most rays from its centroid leave through back faces. Two sets of
// five directions in the tangent frame, each the normal and four 60 degrees off it: along the
// frame's axes, and turned 0.4 rad off them with the first 15 degrees off the normal. A ray
// that leaves a solid through a face lying in another object's face (a block flush with a
// wall, a partition's top in the ceiling) meets a tie that Embree breaks either way. Frame
// tangents follow the world axes, as do most walls: the axis set runs parallel to a thin
// floor-to-ceiling partition and ties on its ends and top, while the turned set leaves the
// sliver under it through the partition's sides; a block flush with two walls ties the turned
// set near the corner, while the axis set leaves through its top and open sides.
std::array<std::array<vec3, 5>, 2> covered_test_directions() {
  const auto spherical = [](float polar, float azimuth) {
    return vec3(std::sin(polar) * std::cos(azimuth), std::sin(polar) * std::sin(azimuth),
                std::cos(polar));
  };
  constexpr float kQuarterTurn = 1.5707963f, kSixtyDegrees = 1.0471976f, kTurn = 0.4f;
  constexpr float kSin = 0.8660254f, kCos = 0.5f;  // exact axes: no stray 1e-8 components
  std::array<std::array<vec3, 5>, 2> sets;
  sets[0] = {vec3(0.0f, 0.0f, 1.0f), vec3(kSin, 0.0f, kCos), vec3(-kSin, 0.0f, kCos),
             vec3(0.0f, kSin, kCos), vec3(0.0f, -kSin, kCos)};
  sets[1][0] = spherical(0.2617994f, kTurn + 0.5f * kQuarterTurn);
  for (int k = 0; k < 4; ++k) sets[1][1 + k] = spherical(kSixtyDegrees, kTurn + k * kQuarterTurn);
  return sets;
}

}  // namespace

std::vector<uint8_t> closed_meshes(const Scene& scene) {
  std::vector<uint8_t> closed(scene.meshes.size(), 0);
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    dvec3 vector_area(0.0);
    double area = 0.0;
    for (const uvec3& tri : mesh.triangles) {
      const dvec3 a(mesh.positions[tri.x]), b(mesh.positions[tri.y]), c(mesh.positions[tri.z]);
      const dvec3 twice = glm::cross(b - a, c - a);
      vector_area += twice;
      area += glm::length(twice);
    }
    closed[m] = area > 0.0 && glm::length(vector_area) <= kClosedMeshTolerance * area;
  }
  return closed;
}

std::vector<uint8_t> covered_triangles(const Mesh& mesh, const Accel& accel,
                                       const std::vector<uint8_t>& closed) {
  std::vector<uint8_t> covered(mesh.triangles.size(), kOpen);
  const Scene& scene = accel.scene();
  // What a probe meets first: the front of a surface (or glass, which lets light through: a
  // floor under a glass block is lit, its caustic), the back of a closed mesh (inside it),
  // the back of an open sheet, or nothing (the void).
  enum class Meets { front, inside, behind, void_ };
  const auto meets = [&](const std::optional<Hit>& hit, vec3 direction) {
    if (!hit) return Meets::void_;
    const int material = scene.meshes[hit->mesh].material;
    const bool glass = material >= 0 && size_t(material) < scene.materials.size() &&
                       scene.materials[size_t(material)].kind == MaterialKind::glass;
    if (glm::dot(direction, hit->geometric_normal) <= 0.0f || glass) return Meets::front;
    return hit->mesh < closed.size() && closed[hit->mesh] ? Meets::inside : Meets::behind;
  };
  // Where no sky lights the void, a point that sees nothing but the void and back faces (the
  // underside of one-sided surfaces: a block's side sunk below a floor) and no lamp gets no
  // light, as an enclosed one gets none. Back faces alone, no void: the point lies under an
  // open sheet (a lamp's back 1 cm off a ceiling), whose light comes in round its edges.
  const bool void_is_dark =
      !scene.sky || (scene.sky->radiance == vec3(0.0f) && scene.sky->texture < 0);
  const auto lamp_reaches = [&](vec3 p, vec3 n) {
    for (const Lamp& lamp : scene.lights) {
      const bool far = lamp.kind == LampKind::directional;
      const vec3 to_lamp = far ? -lamp.direction : lamp.position - p;
      const float distance = far ? 1e30f : glm::length(to_lamp);
      if (distance <= 0.0f || glm::dot(to_lamp, n) <= 0.0f) continue;
      Ray ray;
      ray.direction = far ? to_lamp : to_lamp / distance;
      ray.origin = offset_ray_origin(p, n, ray.direction);
      ray.tmin = 0.0f;
      ray.tmax = far ? 1e30f : distance;
      if (!accel.occluded(ray)) return true;
    }
    return false;
  };
  const std::array<std::array<vec3, 5>, 2> direction_sets = covered_test_directions();
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const vec3 n = triangle_normal(mesh, t);
    if (n == vec3(0.0f)) continue;
    const uvec3 tri = mesh.triangles[t];
    const vec3 centroid =
        (mesh.positions[tri.x] + mesh.positions[tri.y] + mesh.positions[tri.z]) / 3.0f;
    const Frame frame(n);
    std::array<int, 4> met{};  // per Meets, over both sets
    const auto probe = [&](const std::array<vec3, 5>& local) {
      std::array<int, 4> count{};  // per Meets, this set's
      for (const vec3& l : local) {
        Ray ray;
        ray.direction = frame.to_world(l);
        ray.origin = offset_ray_origin(centroid, n, ray.direction);
        ray.tmin = 0.0f;
        ray.tmax = 1e30f;
        const Meets what = meets(accel.intersect(ray), ray.direction);
        ++met[size_t(what)];
        ++count[size_t(what)];
      }
      return count;
    };
    const auto most = [](const std::array<int, 4>& count, Meets what) {
      return count[size_t(what)] >= 3;
    };
    // An open triangle sees no back face along the axes: the second set costs only the rest.
    const std::array<int, 4> axes = probe(direction_sets[0]);
    if (most(axes, Meets::inside)) {
      covered[t] = kCovered;
    } else if (axes[size_t(Meets::inside)] > 0 || axes[size_t(Meets::behind)] > 0) {
      const std::array<int, 4> turned = probe(direction_sets[1]);
      if (most(turned, Meets::inside) ||
          (void_is_dark && met[size_t(Meets::front)] == 0 && met[size_t(Meets::void_)] > 0 &&
           !lamp_reaches(centroid, n)))
        covered[t] = kCovered;
      else if (most(axes, Meets::behind) || most(turned, Meets::behind))
        covered[t] = kSheltered;
    }
  }
  return covered;
}

}  // namespace lb
