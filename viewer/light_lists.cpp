#include "viewer/light_lists.h"

#include <algorithm>
#include <chrono>
#include <map>

#include "viewer/box_clusters.h"
#include "viewer/mesh_chunks.h"

namespace lb {

namespace {

constexpr size_t kChunksPerCluster = 24;
// The cube lookup reads p moved toward the light point by half a texel times tan(theta), at
// most 4 (kShadowRayOffsetTan), and beyond that along the normal by at most half a texel
// (shaders/shadows.glsl: within 5 dist / resolution of p), and filters the 2 x 2 texels around
// it (centres within sqrt(2) texels, 2 dist / resolution each at that depth): 7.83 dist /
// resolution in all, with dist bounded by the box's furthest corner; boxes grow by 8 (plus
// the margin against rounding).
constexpr float kTexelsGrown = 8.0f;
// Angle margin (rad, as a cosine) of the per-triangle side tests: the shader's derivative
// normal and interpolated positions are good to ~1e-4 relative (0.01 kept the lights of
// a ceiling 2 cm above a light 5 m away).
constexpr float kSideMargin = 1e-3f;

enum Reach : char { kZero = 0, kPending = 1, kReached = 2 };

// `v` strictly on the side `n` points to, seen from every one of `p`: by the angle margin,
// or with `precise` (an interpolated vertex normal, no derivatives) by `epsilon` m.
bool above_all(vec3 n, vec3 v, const vec3 p[3], bool precise = false, float epsilon = 0.0f) {
  for (int j = 0; j < 3; ++j) {
    const vec3 d = v - p[j];
    const float margin = precise ? epsilon : kSideMargin * glm::length(d);
    if (!(glm::dot(n, d) > margin)) return false;
  }
  return true;
}

// Whether light `light`'s term is provably zero on triangle `p` (or its lookups all read a
// shadow with a shadow point above the horizon, the queries having found none visible).
// `normals`: the vertex normals, or null (then the shading normal is the winding's, +-n);
// `bumped`: the shading normal is anything (only the horizon case can help). `epsilon` (m):
// what rounding may move the shader's light heights dot(n, v - p) by.
bool zero_on_triangle(const vec3 p[3], vec3 n, const vec3* normals, bool bumped,
                      const std::vector<vec3>& light_vertices, const vec3* points, int count,
                      float epsilon) {
  auto some_point_above = [&](vec3 side) {
    for (int k = 0; k < count; ++k) {
      if (above_all(side, points[k], p)) return true;
    }
    return false;
  };
  // Every light vertex strictly below the horizon of `normal` seen from every corner; a
  // vertex normal is exact, a derivative normal (no normals) takes the angle margin.
  auto below_horizon = [&](vec3 normal) {
    for (const vec3& v : light_vertices) {
      if (!above_all(-normal, v, p, normals != nullptr, epsilon)) return false;
    }
    return true;
  };
  // The derivative normal's side: the winding's without normals (either way round: mirrored
  // passes flip it), else the interpolated normal's (known when all vertex normals agree).
  bool up = true, down = true;
  if (normals) {
    float lo = 1.0f, hi = -1.0f;
    for (int i = 0; i < 3; ++i) {
      lo = std::min(lo, glm::dot(normals[i], n));
      hi = std::max(hi, glm::dot(normals[i], n));
    }
    up = hi > -0.05f;
    down = lo < 0.05f;
  }
  if ((!up || some_point_above(n)) && (!down || some_point_above(-n))) return true;
  if (bumped) return false;
  if (!normals) {
    // Per side: a point above it, or the light wholly below its horizon (n_shading = side).
    return (some_point_above(n) || below_horizon(n)) && (some_point_above(-n) || below_horizon(-n));
  }
  // The interpolated normal sum_i b_i n_i at sum_j b_j p_j: below for every pair => below.
  for (int i = 0; i < 3; ++i) {
    if (!below_horizon(normals[i])) return false;
  }
  return true;
}

}  // namespace

LightLists LightLists::all_lights(const GpuScene& scene) {
  LightLists lists;
  lists.light_count_ = int(scene.lights().lights.size());
  for (const GpuMesh& mesh : scene.meshes()) {
    lists.shadowed_.emplace_back(mesh.chunks.size(), glm::ivec2(0, lists.light_count_));
    for (const MeshChunk& chunk : mesh.chunks) lists.boxes_.push_back(chunk.bounds);
  }
  lists.unshadowed_ = lists.shadowed_;
  lists.mean_ = lists.max_ = lists.light_count_;
  lists.upload(scene, false);
  return lists;
}

LightLists::LightLists(const GpuScene& scene) {
  const GpuLights& lights = scene.lights();
  light_count_ = int(lights.lights.size());
  margin_ = 1e-4f * std::max(scene.bounds().diagonal(), 1e-3f);
  for (size_t m = 0; m < scene.meshes().size(); ++m) {
    const GpuMesh& mesh = scene.meshes()[m];
    const bool diffuse = scene.scene().materials[size_t(mesh.material)].is_diffuse();
    for (size_t c = 0; c < mesh.chunks.size(); ++c) {
      boxes_.push_back(mesh.chunks[c].bounds);
      chunk_of_.emplace_back(m, c);
      receives_.push_back(diffuse && mesh.index_count > 0);
    }
  }
  // Emitting side: behind every light triangle's plane by a margin the shader's float test
  // (lights.glsl, relative to the shaded point) cannot cross: 1e-5 of the scene.
  const float behind = 1e-5f * std::max(scene.bounds().diagonal(), 1e-3f);
  reach_.assign(size_t(light_count_) * boxes_.size(), kZero);
  for (int l = 0; l < light_count_; ++l) {
    const AreaLight& light = lights.lights[size_t(l)];
    const Mesh& mesh = scene.scene().meshes[size_t(light.mesh)];
    for (size_t g = 0; g < boxes_.size(); ++g) {
      if (!receives_[g] || boxes_[g].empty()) continue;
      bool in_front = light.two_sided;  // emits on both sides: every box is in front
      for (size_t k = 0; k < light.triangles.size() && !in_front; ++k) {
        const vec3 n = triangle_normal(mesh, light.triangles[k]);
        const vec3 a = mesh.positions[mesh.triangles[light.triangles[k]].x];
        const Bounds& b = boxes_[g];
        // The box corner furthest along n.
        const vec3 corner{n.x > 0 ? b.max.x : b.min.x, n.y > 0 ? b.max.y : b.min.y,
                          n.z > 0 ? b.max.z : b.min.z};
        in_front = !(glm::dot(n, corner - a) < -behind);
      }
      if (in_front) reach(l, g) = kPending;
    }
  }
  std::vector<Bounds> boxes = boxes_;
  for (size_t g = 0; g < boxes.size(); ++g) {
    if (!receives_[g]) boxes[g] = Bounds();  // in no cluster: never queried
  }
  for (BoxCluster& c : cluster_boxes(boxes, kChunksPerCluster))
    clusters_.push_back({c.bounds, std::move(c.members)});
  queries_ = std::make_unique<BoxQueries>();
}

void LightLists::test_face(int light, vec3 point, const Frustum& frustum, bool drawn, float near,
                           int resolution) {
  auto grown = [&](const Bounds& b) {
    float furthest = 0.0f;
    for (int c = 0; c < 8; ++c) {
      const vec3 corner{(c & 1) ? b.max.x : b.min.x, (c & 2) ? b.max.y : b.min.y,
                        (c & 4) ? b.max.z : b.min.z};
      furthest = std::max(furthest, glm::length(corner - point));
    }
    const float d = kTexelsGrown * furthest / float(resolution) + margin_;
    return Bounds{b.min - vec3(d), b.max + vec3(d)};
  };
  enum { kUnseen, kSeen, kQuery };
  auto classify = [&](const Bounds& g) {
    if (!frustum.may_see(g)) return kUnseen;
    // A face that drew nothing reads "lit" everywhere; the near plane may clip a close box.
    if (!drawn || box_distance(g, point) <= 2.0f * near + margin_) return kSeen;
    return kQuery;
  };
  std::vector<Bounds> boxes;
  std::vector<size_t> asked, open;
  std::vector<char> answers;
  // The boxes gathered, tested; then `on_visible` of each one asked that showed a sample.
  auto ask = [&](auto on_visible) {
    queries_->test(boxes, GL_LEQUAL, answers);
    queries_issued_ += int(boxes.size());
    for (size_t j = 0; j < asked.size(); ++j) {
      if (answers[j]) on_visible(asked[j]);
    }
    boxes.clear();
    asked.clear();
  };
  for (size_t c = 0; c < clusters_.size(); ++c) {
    const Cluster& cluster = clusters_[c];
    const bool pending = std::any_of(cluster.chunks.begin(), cluster.chunks.end(),
                                     [&](size_t g) { return reach(light, g) == kPending; });
    if (!pending) continue;
    const Bounds g = grown(cluster.bounds);
    const int kind = classify(g);
    if (kind == kSeen) open.push_back(c);
    if (kind != kQuery) continue;
    boxes.push_back(g);
    asked.push_back(c);
  }
  ask([&](size_t c) { open.push_back(c); });
  for (size_t c : open) {
    for (size_t g : clusters_[c].chunks) {
      if (reach(light, g) != kPending) continue;
      const Bounds b = grown(boxes_[g]);
      const int kind = classify(b);
      if (kind == kSeen) reach(light, g) = kReached;
      if (kind != kQuery) continue;
      boxes.push_back(b);
      asked.push_back(g);
    }
  }
  ask([&](size_t g) { reach(light, g) = kReached; });
}

void LightLists::finish(const GpuScene& scene, const std::vector<vec3>& points,
                        const std::vector<int>& start, const std::vector<int>& count) {
  const auto started = std::chrono::steady_clock::now();
  queries_.reset();
  const GpuLights& lights = scene.lights();
  std::vector<std::vector<vec3>> light_vertices(static_cast<size_t>(light_count_));
  for (int l = 0; l < light_count_; ++l) {
    const AreaLight& light = lights.lights[size_t(l)];
    const Mesh& mesh = scene.scene().meshes[size_t(light.mesh)];
    for (uint32_t t : light.triangles) {
      for (int k = 0; k < 3; ++k)
        light_vertices[size_t(l)].push_back(mesh.positions[mesh.triangles[t][k]]);
    }
  }
  // Float rounding of v - p and the dot product: a few ulp of the largest coordinate.
  const Bounds& all = scene.bounds();
  const vec3 extent = glm::max(glm::abs(all.min), glm::abs(all.max));
  const float epsilon = 1e-5f * (std::max({extent.x, extent.y, extent.z, 1.0f}) + all.diagonal());
  // Chunks the cubes found unlit: the horizon case, triangle by triangle.
  size_t cached_mesh = SIZE_MAX;
  MeshChunks order;
  for (size_t g = 0; g < boxes_.size(); ++g) {
    const auto [m, c] = chunk_of_[g];
    const GpuMesh& gpu = scene.meshes()[m];
    const Mesh& mesh = scene.scene().meshes[m];
    const Material& material = scene.scene().materials[size_t(gpu.material)];
    const bool bumped = material.bump != BumpKind::none && scene.texture(material.bump_texture);
    const MeshChunk& chunk = gpu.chunks[c];
    if (gpu.chunks.size() > 1 && cached_mesh != m) {
      order = make_mesh_chunks(mesh);
      cached_mesh = m;
    }
    for (int l = 0; l < light_count_; ++l) {
      if (reach(l, g) != kPending) continue;
      const size_t first = size_t(start[size_t(l)]);
      for (uint32_t k = chunk.first_triangle; k < chunk.first_triangle + chunk.triangle_count;
           ++k) {
        const uint32_t t = gpu.chunks.size() > 1 ? order.order[k] : k;
        const uvec3 tri = mesh.triangles[t];
        const vec3 p[3] = {mesh.positions[tri.x], mesh.positions[tri.y], mesh.positions[tri.z]};
        const vec3 normals[3] = {gpu.has_normals ? mesh.normals[tri.x] : vec3(0.0f),
                                 gpu.has_normals ? mesh.normals[tri.y] : vec3(0.0f),
                                 gpu.has_normals ? mesh.normals[tri.z] : vec3(0.0f)};
        const vec3 n = triangle_normal(mesh, t);
        if (n == vec3(0.0f)) continue;  // degenerate: rasterises nothing
        if (!zero_on_triangle(p, n, gpu.has_normals ? normals : nullptr, bumped,
                              light_vertices[size_t(l)], points.data() + first, count[size_t(l)],
                              epsilon)) {
          reach(l, g) = kReached;
          break;
        }
      }
    }
  }
  upload(scene, true);
  finish_seconds_ =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
}

void LightLists::upload(const GpuScene& scene, bool from_reach) {
  std::vector<int> indices;
  for (int l = 0; l < light_count_; ++l) indices.push_back(l);  // all lights at 0
  std::map<std::vector<int>, int> known{{indices, 0}};
  auto range = [&](const std::vector<int>& list) {
    auto [it, added] = known.emplace(list, int(indices.size()));
    if (added) indices.insert(indices.end(), list.begin(), list.end());
    return glm::ivec2(it->second, int(list.size()));
  };
  if (from_reach) {
    shadowed_.clear();
    unshadowed_.clear();
    size_t g = 0, receivers = 0, kept = 0;
    max_ = 0;
    std::vector<int> lit, front;
    for (const GpuMesh& mesh : scene.meshes()) {
      shadowed_.emplace_back();
      unshadowed_.emplace_back();
      for (size_t c = 0; c < mesh.chunks.size(); ++c, ++g) {
        lit.clear();
        front.clear();
        for (int l = 0; l < light_count_; ++l) {
          if (reach(l, g) != kZero) front.push_back(l);
          if (reach(l, g) == kReached) lit.push_back(l);
        }
        shadowed_.back().push_back(range(lit));
        unshadowed_.back().push_back(range(front));
        if (receives_[g]) {
          ++receivers;
          kept += lit.size();
          max_ = std::max(max_, int(lit.size()));
        }
      }
    }
    mean_ = receivers ? double(kept) / double(receivers) : 0.0;
    reach_ = {};
  }
  if (indices.empty()) indices.push_back(0);  // a buffer texture needs a texel
  indices_ = gl::make_buffer_texture(GL_R32I, indices.data(), indices.size() * sizeof(int));
  indices_cpu_ = std::move(indices);
  gl::check_errors("uploading the light lists");
}

}  // namespace lb
