#include "viewer/occlusion_culler.h"

#include <algorithm>

namespace lb {

namespace {

// Meshes drawn first, untested (the light's own room), and per tested batch: each batch is
// one wait for query results.
constexpr size_t kFirstDrawn = 16;
constexpr size_t kBatch = 128;

float box_distance(const Bounds& box, vec3 p) {
  const vec3 outside = glm::max(glm::max(box.min - p, p - box.max), vec3(0.0f));
  return glm::length(outside);
}

}  // namespace

OcclusionCuller::OcclusionCuller() {
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
}

OcclusionCuller::~OcclusionCuller() {
  if (!queries_.empty()) glDeleteQueries(GLsizei(queries_.size()), queries_.data());
}

void OcclusionCuller::draw_casters(const GpuScene& scene, const Frustum& frustum, vec3 eye,
                                   float near, DrawCounts& counts) {
  std::vector<std::pair<float, size_t>> order;
  for (size_t m = 0; m < scene.meshes().size(); ++m) {
    const GpuMesh& mesh = scene.meshes()[m];
    if (mesh.index_count == 0) continue;
    if (scene.scene().materials[size_t(mesh.material)].is_emitter()) continue;
    if (scene.culled(m, frustum, counts)) continue;
    order.emplace_back(box_distance(mesh.bounds, eye), m);
  }
  std::sort(order.begin(), order.end());
  const size_t first = std::min(order.size(), kFirstDrawn);
  for (size_t i = 0; i < first; ++i) scene.draw_mesh(order[i].second, frustum, counts);
  // Boxes grow by a margin so that they cover every pixel their meshes do and lie in front of
  // them, whatever the rounding (1e-4 of the scene, 1 cm on a 100 m level).
  const float margin = 1e-4f * std::max(scene.bounds().diagonal(), 1e-3f);
  std::vector<vec3> corners;
  std::vector<size_t> tested;
  std::vector<char> visible;
  for (size_t begin = first; begin < order.size(); begin += kBatch) {
    const size_t end = std::min(order.size(), begin + kBatch);
    corners.clear();
    tested.clear();
    for (size_t i = begin; i < end; ++i) {
      if (order[i].first <= 2.0f * near + margin) continue;  // the near plane may clip it
      const Bounds& b = scene.meshes()[order[i].second].bounds;
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
      const size_t m = order[i].second;
      if (visible[i - begin]) {
        scene.draw_mesh(m, frustum, counts);
      } else {
        counts.chunks_total += int(scene.meshes()[m].chunks.size());
        counts.triangles_total += size_t(scene.meshes()[m].index_count / 3);
      }
    }
  }
  glBindVertexArray(0);
}

}  // namespace lb
