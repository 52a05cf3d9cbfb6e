#pragma once
// Occlusion queries of axis-aligned boxes against the depth already in the bound target: each
// box is drawn (its 12 triangles, no depth, colour or stencil writes, no polygon offset) with
// the bound program inside one GL_ANY_SAMPLES_PASSED query, and the answers are waited for, so
// no timing enters a result. A box that shows no sample lies wholly behind the depth drawn, as
// far as the rasteriser's samples go.

#include <vector>

#include "bake/scene.h"
#include "viewer/gl_resources.h"

namespace lb {

class BoxQueries {
 public:
  BoxQueries();
  ~BoxQueries();
  BoxQueries(const BoxQueries&) = delete;
  BoxQueries& operator=(const BoxQueries&) = delete;

  // visible[i] = whether any sample of boxes[i] passed `depth_func` (GL_LESS, GL_LEQUAL, ...).
  void test(const std::vector<Bounds>& boxes, GLenum depth_func, std::vector<char>& visible);

 private:
  gl::VertexArray vertex_array_;
  gl::Buffer corners_, indices_;
  std::vector<GLuint> queries_;
};

}  // namespace lb
