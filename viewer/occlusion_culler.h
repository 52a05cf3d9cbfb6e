#pragma once
// Occlusion culling for depth-only passes (the area lights' shadow cubes): the meshes a face's
// frustum may see, nearest first; the nearest few are drawn, then each further batch's boxes
// are tested against the depth drawn so far with occlusion queries (waiting for the results,
// so no timing enters) and only the meshes whose box shows a sample are drawn. A depth map is
// the nearest depth of everything drawn, whatever the order, and a mesh is skipped only when
// its whole box lies behind that depth, so the map is the same bits as drawing everything.
// Inside a room, the walls hide the rest of a level.

#include <vector>

#include "viewer/gl_resources.h"
#include "viewer/gpu_scene.h"

namespace lb {

class OcclusionCuller {
 public:
  OcclusionCuller();
  ~OcclusionCuller();
  OcclusionCuller(const OcclusionCuller&) = delete;
  OcclusionCuller& operator=(const OcclusionCuller&) = delete;

  // Draws the shadow casters (emitters excluded) into the bound depth target with the bound
  // program (its world-to-clip is `frustum`'s), seen from `eye`; `near` is the pass's near
  // plane distance (boxes that close are drawn untested: the plane may clip their faces).
  void draw_casters(const GpuScene& scene, const Frustum& frustum, vec3 eye, float near,
                    DrawCounts& counts);

 private:
  gl::VertexArray boxes_;
  gl::Buffer corners_, indices_;
  std::vector<GLuint> queries_;
};

}  // namespace lb
