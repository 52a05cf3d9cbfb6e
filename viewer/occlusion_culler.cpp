#include "viewer/occlusion_culler.h"

#include <algorithm>

namespace lb {

namespace {

// Clusters drawn first, untested (the light's own room), and the first tested batch; each
// batch is 4 times the one before, so a face waits for query results a few times only (each
// wait drains llvmpipe's queue).
constexpr size_t kFirstDrawn = 2;
constexpr size_t kFirstBatch = 16;
constexpr size_t kMeshesPerCluster = 24;

float box_distance(const Bounds& box, vec3 p) {
  const vec3 outside = glm::max(glm::max(box.min - p, p - box.max), vec3(0.0f));
  return glm::length(outside);
}

}  // namespace

OcclusionCuller::OcclusionCuller(const GpuScene& scene) {
  boxes_ = gl::make_vertex_array();
  corners_ = gl::make_buffer();
  indices_ = gl::make_buffer();
  glBindVertexArray(boxes_.get());
  glBindBuffer(GL_ARRAY_BUFFER, corners_.get());
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(vec3), nullptr);
  // Corner c has x, y, z from bits 0, 1, 2 (0: min, 1: max); two triangles per face.
  const uint32_t faces[6][4] = {{0, 2, 6, 4}, {1, 5, 7, 3}, {0, 4, 5, 1},
                                {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 6, 7, 5}};
  std::vector<uint32_t> index;
  for (const auto& f : faces) index.insert(index.end(), {f[0], f[1], f[2], f[0], f[2], f[3]});
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, indices_.get());
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(index.size() * sizeof(uint32_t)), index.data(),
               GL_STATIC_DRAW);
  glBindVertexArray(0);

  // The grid: cells of equal volume-ish, about kMeshesPerCluster casters each.
  std::vector<size_t> casters;
  Bounds all;
  for (size_t m = 0; m < scene.meshes().size(); ++m) {
    const GpuMesh& mesh = scene.meshes()[m];
    if (mesh.index_count == 0 || mesh.bounds.empty()) continue;
    if (scene.scene().materials[size_t(mesh.material)].is_emitter()) continue;
    casters.push_back(m);
    all.extend(0.5f * (mesh.bounds.min + mesh.bounds.max));
  }
  if (casters.empty()) return;
  const vec3 extent = glm::max(all.extent(), vec3(1e-6f * std::max(all.diagonal(), 1e-3f)));
  const float cells = std::max(1.0f, float(casters.size()) / float(kMeshesPerCluster));
  const float side = std::cbrt(extent.x * extent.y * extent.z / cells);
  glm::ivec3 dims;
  for (int a = 0; a < 3; ++a) dims[a] = std::clamp(int(std::ceil(extent[a] / side)), 1, 64);
  std::vector<int> cell_of(casters.size());
  std::vector<int> slot(size_t(dims.x * dims.y * dims.z), -1);
  for (size_t i = 0; i < casters.size(); ++i) {
    const Bounds& b = scene.meshes()[casters[i]].bounds;
    const vec3 t = (0.5f * (b.min + b.max) - all.min) / extent;
    glm::ivec3 c;
    for (int a = 0; a < 3; ++a) c[a] = std::clamp(int(t[a] * float(dims[a])), 0, dims[a] - 1);
    int& s = slot[size_t((c.z * dims.y + c.y) * dims.x + c.x)];
    if (s < 0) {
      s = int(clusters_.size());
      clusters_.emplace_back();
    }
    Cluster& cluster = clusters_[size_t(s)];
    cluster.meshes.push_back(casters[i]);
    cluster.bounds.extend(b.min);
    cluster.bounds.extend(b.max);
  }
}

OcclusionCuller::~OcclusionCuller() {
  if (!queries_.empty()) glDeleteQueries(GLsizei(queries_.size()), queries_.data());
}

void OcclusionCuller::draw_casters(const GpuScene& scene, const Frustum& frustum, vec3 eye,
                                   float near, DrawCounts& counts) {
  auto skip = [&](const Cluster& cluster) {
    for (size_t m : cluster.meshes) {
      counts.chunks_total += int(scene.meshes()[m].chunks.size());
      counts.triangles_total += size_t(scene.meshes()[m].index_count / 3);
    }
  };
  auto draw = [&](const Cluster& cluster) {
    for (size_t m : cluster.meshes) {
      if (!scene.culled(m, frustum, counts)) scene.draw_mesh(m, frustum, counts);
    }
  };
  std::vector<std::pair<float, size_t>> order;
  for (size_t c = 0; c < clusters_.size(); ++c) {
    if (!frustum.may_see(clusters_[c].bounds)) {
      skip(clusters_[c]);
      continue;
    }
    order.emplace_back(box_distance(clusters_[c].bounds, eye), c);
  }
  std::sort(order.begin(), order.end());
  const size_t first = std::min(order.size(), kFirstDrawn);
  for (size_t i = 0; i < first; ++i) draw(clusters_[order[i].second]);
  // Boxes grow by a margin so that they cover every pixel their meshes do and lie in front of
  // them, whatever the rounding (1e-4 of the scene, 1 cm on a 100 m level).
  const float margin = 1e-4f * std::max(scene.bounds().diagonal(), 1e-3f);
  std::vector<vec3> corners;
  std::vector<size_t> tested;
  std::vector<char> visible;
  size_t batch = kFirstBatch;
  for (size_t begin = first; begin < order.size(); begin += batch, batch *= 4) {
    const size_t end = std::min(order.size(), begin + batch);
    corners.clear();
    tested.clear();
    for (size_t i = begin; i < end; ++i) {
      if (order[i].first <= 2.0f * near + margin) continue;  // the near plane may clip it
      const Bounds& b = clusters_[order[i].second].bounds;
      for (int c = 0; c < 8; ++c) {
        corners.push_back({(c & 1) ? b.max.x + margin : b.min.x - margin,
                           (c & 2) ? b.max.y + margin : b.min.y - margin,
                           (c & 4) ? b.max.z + margin : b.min.z - margin});
      }
      tested.push_back(i);
    }
    if (queries_.size() < tested.size()) {
      const size_t old = queries_.size();
      queries_.resize(tested.size());
      glGenQueries(GLsizei(queries_.size() - old), queries_.data() + old);
    }
    if (!tested.empty()) {
      glBindVertexArray(boxes_.get());
      glBindBuffer(GL_ARRAY_BUFFER, corners_.get());
      glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(corners.size() * sizeof(vec3)), corners.data(),
                   GL_STREAM_DRAW);
      // Test only: no depth writes, and without the pass's polygon offset (that pushes the
      // drawn depth away, so a box in front passes all the more).
      glDepthMask(GL_FALSE);
      const GLboolean offset = glIsEnabled(GL_POLYGON_OFFSET_FILL);
      glDisable(GL_POLYGON_OFFSET_FILL);
      for (size_t j = 0; j < tested.size(); ++j) {
        glBeginQuery(GL_ANY_SAMPLES_PASSED, queries_[j]);
        glDrawElementsBaseVertex(GL_TRIANGLES, 36, GL_UNSIGNED_INT, nullptr, GLint(8 * j));
        glEndQuery(GL_ANY_SAMPLES_PASSED);
      }
      if (offset) glEnable(GL_POLYGON_OFFSET_FILL);
      glDepthMask(GL_TRUE);
    }
    visible.assign(end - begin, 1);
    for (size_t j = 0; j < tested.size(); ++j) {
      GLuint passed = 0;
      glGetQueryObjectuiv(queries_[j], GL_QUERY_RESULT, &passed);  // waits
      visible[tested[j] - begin] = passed != 0;
    }
    for (size_t i = begin; i < end; ++i) {
      const Cluster& cluster = clusters_[order[i].second];
      if (visible[i - begin]) {
        draw(cluster);
      } else {
        skip(cluster);
      }
    }
  }
  glBindVertexArray(0);
}

}  // namespace lb
