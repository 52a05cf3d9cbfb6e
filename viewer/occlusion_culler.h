#pragma once
// Occlusion culling for depth-only passes (the area lights' shadow cubes). The meshes are
// grouped once into clusters by a uniform grid over the scene (about kMeshesPerCluster each,
// so a level's cells are about its rooms), each with the box of its meshes. Per face: the
// clusters its frustum may see, nearest first; the nearest few are drawn, then each further
// batch's boxes are tested against the depth drawn so far with occlusion queries (waiting for
// the results, so no timing enters) and only the clusters whose box shows a sample are drawn.
// One query per cluster, not per mesh: a query is a draw call, and draw calls are the cost. A depth
// map is the nearest depth of everything drawn, whatever the order, and a mesh is skipped only when
// its whole box lies behind that depth, so the map is the same bits as drawing everything.
// Inside a room, the walls hide the rest of a level.

#include <vector>

#include "viewer/box_queries.h"
#include "viewer/gpu_scene.h"

namespace lb {

class OcclusionCuller {
 public:
  explicit OcclusionCuller(const GpuScene& scene);

  // Draws `scene`'s (the constructor's) shadow casters (emitters excluded) into the bound depth
  // target with the bound program (its world-to-clip is `frustum`'s), seen from `eye`; `near` is
  // the pass's near plane distance (boxes that close are drawn untested: the plane may clip their
  // faces).
  void draw_casters(const GpuScene& scene, const Frustum& frustum, vec3 eye, float near,
                    DrawCounts& counts);

 private:
  BoxQueries queries_;
  struct Cluster {
    Bounds bounds;
    std::vector<size_t> meshes;  // shadow casters only, in scene order
  };
  std::vector<Cluster> clusters_;
};

}  // namespace lb
