#include "bake/radiosity/patches.h"

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <algorithm>
#include <bit>
#include <cmath>
#include <ctime>
#include <deque>
#include <optional>
#include <queue>
#include <span>
#include <unordered_map>

#include "bake/accel.h"
#include "bake/contact_cuts.h"
#include "bake/sampling.h"

namespace lb {

namespace {

using OpenTriMesh = OpenMesh::TriMesh_ArrayKernelT<>;

double thread_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

// Cutter meshes whose footprint fits in a square a quarter of the patch edge wide do not cut
// (contact_cuts.h: at most 1/16 = 6.25% of a patch hidden under one).
constexpr float kMinCutterFootprint = 0.25f;
// Cutters hovering within an eighth of the patch edge cut along their outline (contact_cuts.h):
// the Cornell box's lamp, 1 cm under its ceiling, at the automatic 12.5 cm patches.
constexpr float kHoverGap = 0.125f;

float cos_degrees(float degrees) {
  return std::cos(degrees * 3.14159265358979f / 180.0f);
}

// Exact position as a hash key; -0 and +0 are the same point.
struct PositionKey {
  uint32_t x, y, z;
  explicit PositionKey(vec3 p)
      : x(std::bit_cast<uint32_t>(p.x + 0.0f)),
        y(std::bit_cast<uint32_t>(p.y + 0.0f)),
        z(std::bit_cast<uint32_t>(p.z + 0.0f)) {}
  bool operator==(const PositionKey&) const = default;
};
struct PositionKeyHash {
  size_t operator()(const PositionKey& k) const { return size_t(hash_seed(k.x, k.y, k.z)); }
};

// Welds vertices by exact position: result[v] is a canonical id shared by coincident vertices.
std::vector<uint32_t> weld_by_position(const std::vector<vec3>& positions) {
  std::unordered_map<PositionKey, uint32_t, PositionKeyHash> first;
  first.reserve(positions.size());
  std::vector<uint32_t> canonical(positions.size());
  for (size_t v = 0; v < positions.size(); ++v)
    canonical[v] = first.try_emplace(PositionKey(positions[v]), uint32_t(v)).first->second;
  return canonical;
}

// Appends the midpoint of vertices a and b; symmetric in a and b (bit for bit), which is what
// keeps seams conforming.
uint32_t append_midpoint(Mesh& mesh, uint32_t a, uint32_t b) {
  auto mid = [](auto x, auto y) { return (x + y) * 0.5f; };
  auto unit_mid = [](vec3 x, vec3 y) {
    const vec3 s = x + y;
    const float length = glm::length(s);
    return length > 0.0f ? s / length : x;
  };
  mesh.positions.push_back(mid(mesh.positions[a], mesh.positions[b]));
  if (!mesh.normals.empty()) mesh.normals.push_back(unit_mid(mesh.normals[a], mesh.normals[b]));
  if (!mesh.uvs.empty()) mesh.uvs.push_back(mid(mesh.uvs[a], mesh.uvs[b]));
  if (!mesh.lightmap_uvs.empty())
    mesh.lightmap_uvs.push_back(mid(mesh.lightmap_uvs[a], mesh.lightmap_uvs[b]));
  if (!mesh.tangents.empty()) {
    const vec4 ta = mesh.tangents[a], tb = mesh.tangents[b];
    mesh.tangents.push_back(vec4(unit_mid(vec3(ta), vec3(tb)), ta.w));
  }
  return uint32_t(mesh.positions.size() - 1);
}

// Triangle neighbours across edges (compressed rows), with vertices welded by position (so
// patches may grow across UV seams; the normal test stops them at creases). Per triangle:
// edge by edge, the other triangles on that edge in ascending order.
struct Neighbours {
  std::vector<uint32_t> offsets;  // triangle t's are at [offsets[t], offsets[t + 1])
  std::vector<uint32_t> ids;
  std::span<const uint32_t> operator[](size_t t) const {
    return {ids.data() + offsets[t], ids.data() + offsets[t + 1]};
  }
};

// A sorted edge list, not a hash map of vectors: the same order, cheaper on big meshes.
Neighbours triangle_neighbours(const Mesh& mesh) {
  const std::vector<uint32_t> weld = weld_by_position(mesh.positions);
  const size_t n = mesh.triangles.size();
  // (welded edge, corner slot 3 t + k), sorted: equal edges form runs, slots ascending.
  std::vector<std::pair<uint64_t, uint32_t>> edges(3 * n);
  for (size_t t = 0; t < n; ++t)
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = weld[mesh.triangles[t][k]], b = weld[mesh.triangles[t][(k + 1) % 3]];
      edges[3 * t + size_t(k)] = {uint64_t(std::min(a, b)) << 32 | std::max(a, b),
                                  uint32_t(3 * t + size_t(k))};
    }
  std::sort(edges.begin(), edges.end());
  // (slot, other triangle) for every pair in a run, then sorted by slot (others ascending).
  std::vector<std::pair<uint32_t, uint32_t>> links;
  links.reserve(3 * n);
  for (size_t begin = 0, end; begin < edges.size(); begin = end) {
    end = begin + 1;
    while (end < edges.size() && edges[end].first == edges[begin].first) ++end;
    for (size_t i = begin; i < end; ++i)
      for (size_t j = begin; j < end; ++j)
        if (edges[j].second / 3 != edges[i].second / 3)
          links.emplace_back(edges[i].second, edges[j].second / 3);
  }
  std::sort(links.begin(), links.end());
  Neighbours neighbours;
  neighbours.offsets.assign(n + 1, 0);
  neighbours.ids.reserve(links.size());
  for (const auto& [slot, other] : links) {
    ++neighbours.offsets[slot / 3 + 1];
    neighbours.ids.push_back(other);
  }
  for (size_t t = 0; t < n; ++t) neighbours.offsets[t + 1] += neighbours.offsets[t];
  return neighbours;
}

struct Grouping {
  std::vector<uint32_t> triangle_patch;  // local patch id per triangle
  uint32_t patch_count = 0;
};

// Step 3: breadth-first growth to the target area, then sliver merging.
// `covered` (per triangle, TriangleCoverage): a patch never mixes covered, sheltered and open
// triangles.
Grouping group_triangles(const Mesh& mesh, float target_area, float crease_cos,
                         const std::vector<uint8_t>& covered) {
  const size_t n = mesh.triangles.size();
  std::vector<vec3> normal(n);
  std::vector<double> area(n);
  for (size_t t = 0; t < n; ++t) {
    normal[t] = triangle_normal(mesh, t);
    area[t] = triangle_area(mesh, t);
  }
  const auto neighbours = triangle_neighbours(mesh);

  constexpr uint32_t unassigned = ~0u;
  std::vector<uint32_t> patch_of(n, unassigned);
  std::vector<double> patch_area;
  std::vector<glm::dvec3> patch_normal_sum;
  std::deque<uint32_t> queue;
  for (size_t seed = 0; seed < n; ++seed) {
    if (patch_of[seed] != unassigned) continue;
    const uint32_t p = uint32_t(patch_area.size());
    patch_area.push_back(0.0);
    patch_normal_sum.emplace_back(0.0);
    queue.assign(1, uint32_t(seed));
    patch_of[seed] = p;
    while (!queue.empty() && patch_area[p] < target_area) {
      const uint32_t f = queue.front();
      queue.pop_front();
      patch_area[p] += area[f];
      patch_normal_sum[p] += area[f] * glm::dvec3(normal[f]);
      for (uint32_t g : neighbours[f]) {
        if (patch_of[g] != unassigned) continue;
        if (covered[g] != covered[seed]) continue;
        if (glm::dot(normal[g], normal[seed]) < crease_cos) continue;
        if (glm::dot(normal[g], normal[f]) < crease_cos) continue;
        patch_of[g] = p;
        queue.push_back(g);
      }
    }
    for (uint32_t f : queue) patch_of[f] = unassigned;  // reached but not taken
  }

  // Slivers (left-overs at the end of a growth) join their smallest compatible neighbour.
  const size_t count = patch_area.size();
  std::vector<uint32_t> parent(count);
  for (size_t p = 0; p < count; ++p) parent[p] = uint32_t(p);
  auto root = [&](uint32_t p) {
    while (parent[p] != p) p = parent[p];
    return p;
  };
  std::vector<std::vector<uint32_t>> members(count);
  for (size_t t = 0; t < n; ++t) members[patch_of[t]].push_back(uint32_t(t));
  for (uint32_t p = 0; p < count; ++p) {
    if (patch_area[p] >= 0.3 * target_area) continue;
    const glm::dvec3 np = glm::normalize(patch_normal_sum[p]);
    uint32_t best = unassigned;
    for (uint32_t t : members[p])
      for (uint32_t g : neighbours[t]) {
        const uint32_t q = root(patch_of[g]);
        if (q == p) continue;
        if (covered[g] != covered[t]) continue;
        if (glm::dot(glm::normalize(patch_normal_sum[q]), np) < double(crease_cos)) continue;
        if (glm::dot(normal[g], normal[t]) < crease_cos) continue;
        if (best == unassigned || patch_area[q] < patch_area[best] ||
            (patch_area[q] == patch_area[best] && q < best))
          best = q;
      }
    if (best == unassigned) continue;
    parent[p] = best;
    patch_area[best] += patch_area[p];
    patch_normal_sum[best] += patch_normal_sum[p];
  }

  Grouping grouping;
  std::vector<uint32_t> compact(count, unassigned);
  grouping.triangle_patch.resize(n);
  for (size_t t = 0; t < n; ++t) {
    const uint32_t r = root(patch_of[t]);
    if (compact[r] == unassigned) compact[r] = grouping.patch_count++;
    grouping.triangle_patch[t] = compact[r];
  }
  return grouping;
}

}  // namespace

namespace {

// sqrt(largest bounding-box face / patches_per_face); 1 for an empty scene.
float patch_size_for(const Scene& scene, float patches_per_face) {
  const Bounds bounds = scene_bounds(scene);
  if (bounds.empty()) return 1.0f;
  vec3 e = bounds.extent();
  std::sort(&e[0], &e[0] + 3);
  float face = e[2] * e[1];
  if (!(face > 0.0f)) face = e[2] * e[2];  // a flat line of geometry: use the longest extent
  if (!(face > 0.0f)) return 1.0f;
  return std::sqrt(face / patches_per_face);
}

// The paper's 32 a wall, capped like the automatic size (the same factor sqrt(8) above it).
float coarse_patch_size(const Scene& scene) {
  return std::min(patch_size_for(scene, 32.0f), std::sqrt(8.0f) * kMaxAutomaticPatchSize);
}

}  // namespace

float automatic_patch_size(const Scene& scene) {
  return std::min(patch_size_for(scene, 256.0f), kMaxAutomaticPatchSize);
}

Mesh split_creases(const Mesh& mesh, float crease_degrees) {
  const float crease_cos = cos_degrees(crease_degrees);
  Mesh out = mesh;
  std::vector<std::vector<uint32_t>> incident(mesh.positions.size());
  for (size_t t = 0; t < mesh.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) incident[mesh.triangles[t][k]].push_back(uint32_t(t));
  for (size_t v = 0; v < mesh.positions.size(); ++v) {
    // Smooth groups: a triangle joins the first group whose first normal is within the angle.
    std::vector<vec3> group_normal;
    std::vector<uint32_t> group_vertex;
    for (uint32_t t : incident[v]) {
      const vec3 n = triangle_normal(mesh, t);
      size_t g = 0;
      while (g < group_normal.size() && glm::dot(group_normal[g], n) < crease_cos &&
             n != vec3(0.0f))
        ++g;
      if (g == group_normal.size()) {
        group_normal.push_back(n);
        group_vertex.push_back(g == 0 ? uint32_t(v) : append_vertex_copy(out, uint32_t(v)));
      }
      for (int k = 0; k < 3; ++k)
        if (mesh.triangles[t][k] == v) out.triangles[t][k] = group_vertex[g];
    }
  }
  return out;
}

Mesh refine_mesh(const Mesh& mesh, float max_edge) {
  Mesh out = mesh;
  out.triangles.clear();
  out.hidden.clear();
  OpenTriMesh topology;
  auto point = [&](uint32_t v) {
    const vec3 p = out.positions[v];
    return OpenTriMesh::Point(p.x, p.y, p.z);
  };
  // OpenMesh vertex i is out's vertex i throughout.
  for (size_t v = 0; v < out.positions.size(); ++v) topology.add_vertex(point(uint32_t(v)));
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (!(triangle_area(mesh, t) > 0.0f)) continue;
    uvec3 tri = mesh.triangles[t];
    auto face = topology.add_face(OpenTriMesh::VertexHandle(int(tri.x)),
                                  OpenTriMesh::VertexHandle(int(tri.y)),
                                  OpenTriMesh::VertexHandle(int(tri.z)));
    if (!face.is_valid()) {
      // Non-manifold here: give this triangle its own vertices. The geometric split rule keeps
      // it conforming with its neighbours all the same.
      for (int k = 0; k < 3; ++k) {
        tri[k] = append_vertex_copy(out, tri[k]);
        topology.add_vertex(point(tri[k]));
      }
      face = topology.add_face(OpenTriMesh::VertexHandle(int(tri.x)),
                               OpenTriMesh::VertexHandle(int(tri.y)),
                               OpenTriMesh::VertexHandle(int(tri.z)));
    }
  }

  auto edge_length = [&](OpenTriMesh::EdgeHandle e) {
    const auto h = topology.halfedge_handle(e, 0);
    return glm::length(out.positions[size_t(topology.to_vertex_handle(h).idx())] -
                       out.positions[size_t(topology.from_vertex_handle(h).idx())]);
  };
  std::priority_queue<std::pair<float, int>> longest;
  for (auto e : topology.edges()) {
    const float length = edge_length(e);
    if (length > max_edge) longest.push({length, e.idx()});
  }
  while (!longest.empty()) {
    const auto [length, index] = longest.top();
    longest.pop();
    const OpenTriMesh::EdgeHandle e(index);
    if (edge_length(e) != length) continue;  // stale: the edge was split since
    const auto h = topology.halfedge_handle(e, 0);
    const uint32_t a = uint32_t(topology.from_vertex_handle(h).idx());
    const uint32_t b = uint32_t(topology.to_vertex_handle(h).idx());
    const uint32_t m = append_midpoint(out, a, b);
    const auto vh = topology.add_vertex(point(m));
    topology.split(e, vh);
    for (auto around : topology.voh_range(vh)) {
      const auto edge = topology.edge_handle(around);
      const float l = edge_length(edge);
      if (l > max_edge) longest.push({l, edge.idx()});
    }
  }

  out.triangles.reserve(topology.n_faces());
  for (auto f : topology.faces()) {
    uvec3 tri;
    int k = 0;
    for (auto v : topology.fv_range(f)) tri[k++] = uint32_t(v.idx());
    out.triangles.push_back(tri);
  }
  return out;
}

double estimate_patch_count(const Scene& scene, float patch_size, bool include_emitters) {
  const double default_size = patch_size > 0.0f ? patch_size : automatic_patch_size(scene);
  double count = 0.0;
  for (const Mesh& mesh : scene.meshes) {
    const Material& material = scene.materials.at(size_t(mesh.material));
    if (!material.is_diffuse() || (material.is_emitter() && !include_emitters)) continue;
    const double h = mesh.bake.patch_size > 0.0f ? mesh.bake.patch_size : default_size;
    count += std::max(double(mesh_area(mesh)) / (h * h), double(mesh.triangles.size()));
  }
  return count;
}

Patches build_patches(const Scene& scene, float patch_size, bool include_emitters,
                      const Accel* accel, bool contact_cuts, const Progress* progress) {
  std::optional<Accel> own_accel;
  if (!contact_cuts)
    accel = nullptr;
  else if (!accel && scene.meshes.size() > 1)
    accel = &own_accel.emplace(scene);
  const float tolerance = contact_tolerance(scene);
  std::optional<BoxGrid> mesh_boxes;
  if (accel) mesh_boxes.emplace(mesh_box_grid(scene));
  const std::vector<uint8_t> closed =
      accel ? closed_meshes(accel->scene()) : std::vector<uint8_t>{};
  Patches result;
  result.default_patch_size = patch_size > 0.0f ? patch_size : automatic_patch_size(scene);
  result.meshes.resize(scene.meshes.size());
  const float crease_cos = cos_degrees(kCreaseAngleDegrees);
  auto takes_patches = [&](const Mesh& mesh) {
    const Material& material = scene.materials.at(size_t(mesh.material));
    return material.is_diffuse() && !(material.is_emitter() && !include_emitters) &&
           !mesh.triangles.empty();
  };
  // Progress in triangles after refinement, about: each mesh's own plus its area over h^2.
  auto work = [&](const Mesh& mesh) {
    const double h = result.default_patch_size;
    return takes_patches(mesh) ? double(mesh.triangles.size()) + mesh_area(mesh) / (h * h) : 0.0;
  };
  double total = 0.0, done = 0.0;
  for (const Mesh& mesh : scene.meshes) total += work(mesh);
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    const Material& material = scene.materials.at(size_t(mesh.material));
    if (!takes_patches(mesh)) continue;
    if (progress) {
      progress->throw_if_cancelled();
      progress->update("radiosity: patches", done / total);
      done += work(mesh);
    }
    float h = mesh.bake.patch_size > 0.0f ? mesh.bake.patch_size : result.default_patch_size;
    // Automatic size on an emitter: the paper's coarse 32 per wall. HQ mode and the viewer
    // draw the refined mesh, and a light cut into many triangles stratifies its samples
    // worse (RasterVsHq's HQ noise 1.0% -> 1.5%), while the light it reflects matters little.
    if (material.is_emitter() && mesh.bake.patch_size <= 0.0f && patch_size <= 0.0f)
      h = std::max(h, coarse_patch_size(scene));

    PatchMesh& out = result.meshes[m];
    double clock = thread_cpu_seconds();
    auto lap = [&clock](double& seconds) {
      const double now = thread_cpu_seconds();
      seconds += now - clock;
      clock = now;
    };
    out.mesh = refine_mesh(split_creases(mesh), std::sqrt(2.0f) * h);
    lap(result.seconds.refine);
    std::vector<uint8_t> covered(out.mesh.triangles.size(), 0);
    if (accel) {
      out.mesh =
          cut_along_contacts(out.mesh, scene, *mesh_boxes, m, tolerance, kMinCutterFootprint * h,
                             kHoverGap * h);
      lap(result.seconds.cuts);
      covered = covered_triangles(out.mesh, *accel, closed);
      lap(result.seconds.coverage);
    }
    const Grouping grouping = group_triangles(out.mesh, h * h, crease_cos, covered);
    const uint32_t first = uint32_t(result.patches.size());
    result.patches.resize(first + grouping.patch_count);
    out.triangle_patch.resize(out.mesh.triangles.size());
    for (size_t t = 0; t < out.mesh.triangles.size(); ++t) {
      const uint32_t p = first + grouping.triangle_patch[t];
      out.triangle_patch[t] = p;
      Patch& patch = result.patches[p];
      patch.mesh = uint32_t(m);
      patch.covered = covered[t] == kCovered;  // kSheltered: a patch of its own, lit
      patch.triangles.push_back(uint32_t(t));
    }
    for (uint32_t p = first; p < result.patches.size(); ++p) {
      Patch& patch = result.patches[p];
      double area = 0.0;
      glm::dvec3 normal(0.0);
      for (uint32_t t : patch.triangles) {
        const double a = triangle_area(out.mesh, t);
        area += a;
        normal += a * glm::dvec3(triangle_normal(out.mesh, t));
        patch.triangle_cdf.push_back(float(area));
      }
      for (float& c : patch.triangle_cdf) c = area > 0.0 ? float(c / area) : 1.0f;
      patch.triangle_cdf.back() = 1.0f;
      patch.area = area;
      const double length = glm::length(normal);
      patch.normal = length > 0.0 ? vec3(normal / length) : vec3(0.0f, 0.0f, 1.0f);
    }
    lap(result.seconds.grouping);
  }
  return result;
}

std::vector<vec3> vertex_radiance_from_patches(const PatchMesh& patch_mesh,
                                               const std::vector<Patch>& patches,
                                               const std::vector<vec3>& patch_radiance) {
  const Mesh& mesh = patch_mesh.mesh;
  const float crease_cos = cos_degrees(kCreaseAngleDegrees);
  const size_t vertex_count = mesh.positions.size();
  std::vector<std::vector<uint32_t>> incident(vertex_count);
  for (size_t t = 0; t < mesh.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) incident[mesh.triangles[t][k]].push_back(uint32_t(t));
  const std::vector<uint32_t> weld = weld_by_position(mesh.positions);
  std::vector<std::vector<uint32_t>> coincident(vertex_count);  // by canonical id
  for (size_t v = 0; v < vertex_count; ++v) coincident[weld[v]].push_back(uint32_t(v));
  std::vector<vec3> normal(mesh.triangles.size());
  for (size_t t = 0; t < mesh.triangles.size(); ++t) normal[t] = triangle_normal(mesh, t);

  std::vector<vec3> radiance(vertex_count, vec3(0.0f));
  std::vector<uint32_t> seen;
  for (size_t v = 0; v < vertex_count; ++v) {
    vec3 own(0.0f);
    for (uint32_t t : incident[v]) own += triangle_area(mesh, t) * normal[t];
    if (incident[v].empty() || glm::length(own) == 0.0f) continue;
    own = glm::normalize(own);
    glm::dvec3 sum(0.0);
    double weight = 0.0;
    for (const bool take_covered : {false, true}) {
      seen.clear();
      for (uint32_t u : coincident[weld[v]])
        for (uint32_t t : incident[u]) {
          if (glm::dot(normal[t], own) < crease_cos) continue;
          const uint32_t p = patch_mesh.triangle_patch[t];
          if (patches[p].covered != take_covered) continue;
          if (std::find(seen.begin(), seen.end(), p) != seen.end()) continue;
          seen.push_back(p);
          sum += patches[p].area * glm::dvec3(patch_radiance[p]);
          weight += patches[p].area;
        }
      if (weight > 0.0) break;
    }
    if (weight > 0.0) radiance[v] = vec3(sum / weight);
  }
  return radiance;
}

}  // namespace lb
