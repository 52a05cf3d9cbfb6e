#include "viewer/box_queries.h"

namespace lb {

BoxQueries::BoxQueries() {
  vertex_array_ = gl::make_vertex_array();
  corners_ = gl::make_buffer();
  indices_ = gl::make_buffer();
  glBindVertexArray(vertex_array_.get());
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

BoxQueries::~BoxQueries() {
  if (!queries_.empty()) glDeleteQueries(GLsizei(queries_.size()), queries_.data());
}

void BoxQueries::test(const std::vector<Bounds>& boxes, GLenum depth_func,
                      std::vector<char>& visible) {
  visible.assign(boxes.size(), 0);
  if (boxes.empty()) return;
  std::vector<vec3> corners;
  corners.reserve(8 * boxes.size());
  for (const Bounds& b : boxes) {
    for (int c = 0; c < 8; ++c) {
      corners.push_back(
          {(c & 1) ? b.max.x : b.min.x, (c & 2) ? b.max.y : b.min.y, (c & 4) ? b.max.z : b.min.z});
    }
  }
  if (queries_.size() < boxes.size()) {
    const size_t old = queries_.size();
    queries_.resize(boxes.size());
    glGenQueries(GLsizei(queries_.size() - old), queries_.data() + old);
  }
  glBindVertexArray(vertex_array_.get());
  glBindBuffer(GL_ARRAY_BUFFER, corners_.get());
  glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(corners.size() * sizeof(vec3)), corners.data(),
               GL_STREAM_DRAW);
  // Test only: no depth, colour or stencil writes (the camera's pre-pass counts coverage in
  // the stencil), and without the pass's polygon offset (that pushes the drawn depth away, so
  // a box in front passes all the more).
  GLint old_func = GL_LESS;
  glGetIntegerv(GL_DEPTH_FUNC, &old_func);
  GLboolean colour_mask[4];
  glGetBooleanv(GL_COLOR_WRITEMASK, colour_mask);
  glDepthFunc(depth_func);
  glDepthMask(GL_FALSE);
  glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
  const GLboolean stencil = glIsEnabled(GL_STENCIL_TEST);
  glDisable(GL_STENCIL_TEST);
  const GLboolean offset = glIsEnabled(GL_POLYGON_OFFSET_FILL);
  glDisable(GL_POLYGON_OFFSET_FILL);
  for (size_t j = 0; j < boxes.size(); ++j) {
    glBeginQuery(GL_ANY_SAMPLES_PASSED, queries_[j]);
    glDrawElementsBaseVertex(GL_TRIANGLES, 36, GL_UNSIGNED_INT, nullptr, GLint(8 * j));
    glEndQuery(GL_ANY_SAMPLES_PASSED);
  }
  if (offset) glEnable(GL_POLYGON_OFFSET_FILL);
  if (stencil) glEnable(GL_STENCIL_TEST);
  glColorMask(colour_mask[0], colour_mask[1], colour_mask[2], colour_mask[3]);
  glDepthMask(GL_TRUE);
  glDepthFunc(GLenum(old_func));
  for (size_t j = 0; j < boxes.size(); ++j) {
    GLuint passed = 0;
    glGetQueryObjectuiv(queries_[j], GL_QUERY_RESULT, &passed);  // waits
    visible[j] = passed != 0;
  }
  glBindVertexArray(0);
}

}  // namespace lb
