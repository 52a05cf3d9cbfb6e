#pragma once
// Occlusion culling for depth-only passes (the area lights' shadow cubes, the camera's depth
// pre-pass). The meshes are grouped once into clusters by a uniform grid over the scene (about
// kMeshesPerCluster each, so a level's cells are about its rooms), each with the box of its
// meshes. Per pass: the clusters its frustum may see, nearest first; the nearest one or two are
// drawn, then each further batch's boxes are tested against the depth drawn so far with
// occlusion queries (waiting for the results, so no timing enters) and only the clusters whose
// box shows a sample are drawn; with occluders first (big meshes of few triangles: walls,
// floors, ceilings), those draw them and are tested again with the box of the rest. One query
// per cluster (two with occluders), not per mesh: a query is a draw call, and draw calls are
// the cost. A depth map is the nearest depth of everything drawn, whatever
// the order, and a mesh is skipped only when its whole box lies behind that depth, so the map
// is the same bits as drawing everything. Inside a room, the walls hide the rest of a level.
// The camera's pre-pass tests with GL_LEQUAL and hands the meshes it drew to its shading pass
// (GL_EQUAL): a skipped mesh lies strictly behind the final depth, so it could not have kept a
// fragment there either.

#include <vector>

#include "viewer/box_queries.h"
#include "viewer/gpu_scene.h"

namespace lb {

class OcclusionCuller {
 public:
  // Which meshes a pass draws: the shadow casters (emitters excluded) or all (the camera);
  // never the alpha-cut ones (viewer/alpha_cut.h), which their pass draws after.
  enum class Members { casters, all };
  explicit OcclusionCuller(const GpuScene& scene, Members members = Members::casters);

  // Draws `scene`'s (the constructor's) members into the bound depth target with the bound
  // program (its world-to-clip is `frustum`'s), seen from `eye`. Boxes within `untested_within`
  // (m) of the eye are drawn untested: the near plane may clip their faces, so it must reach
  // past the near plane's farthest corner. A box shows a sample where it passes `depth_func`
  // against the depth drawn so far. `drawn`, if given, gets one flag per scene mesh: 1 for the
  // meshes of the clusters drawn. Meshes are drawn at the levels of detail `detail` picks.
  void draw(const GpuScene& scene, const Frustum& frustum, vec3 eye, float untested_within,
            GLenum depth_func, DrawCounts& counts, std::vector<char>* drawn = nullptr,
            const DetailView& detail = {});
  // Whether draw tests the occluders before the other clusters (on by default).
  void set_occluders_first(bool on) { occluders_first_ = on; }
  // Box queries issued by the last draw.
  int queries() const { return queries_issued_; }
  // Triangles of the last draw's clusters in the frustum, and of those its queries hid.
  size_t triangles_in_view() const { return in_view_; }
  size_t triangles_hidden() const { return hidden_; }

 private:
  size_t first_drawn_;  // nearest clusters drawn untested
  int queries_issued_ = 0;
  size_t in_view_ = 0, hidden_ = 0;
  BoxQueries queries_;
  struct Cluster {
    Bounds bounds;
    std::vector<size_t> meshes;     // members only, in scene order
    std::vector<size_t> occluders;  // of those, the big cheap ones (walls, floors, ceilings)
    std::vector<size_t> others;     // the rest, and their box
    Bounds others_bounds;
    size_t triangles = 0;
  };
  std::vector<Cluster> clusters_;
  std::vector<float> distance_;  // per cluster: from the eye, this pass
  bool occluders_first_ = true;
};

}  // namespace lb
