#pragma once
// Per-chunk light lists: for each draw chunk of the scene (viewer/mesh_chunks.h), the area
// lights that can give any point of it direct light, so the scene shader loops over that
// list instead of over every light (shaders/lights.glsl u_light_list). A light is left out of
// a chunk only where its term is provably exactly zero, so full-mode images keep their bits:
//  - emitting side: the chunk's box lies wholly behind the plane of every one of the light's
//    triangles (lights.glsl then adds nothing, whatever the shading normal); this list also
//    holds with shadows off;
//  - shadow cubes: no sample of the chunk's box, grown to cover the lookup's offset
//    and 2 x 2 filter, passes the depth test in any face of any of the light's cubes
//    (occlusion queries right after each face is drawn, viewer/box_queries.h; clusters of
//    chunks first), so every lookup of shaders/shadows.glsl reads 0; and, per triangle, the
//    lookup is not the "no shadow point above the horizon" case (which counts as visible)
//    unless the light's term is 0 there too.
// Lamps keep the full loop (a scene has few).

#include <memory>
#include <vector>

#include "viewer/box_queries.h"
#include "viewer/frustum.h"
#include "viewer/gpu_scene.h"

namespace lb {

class LightLists {
 public:
  LightLists() = default;
  // Every chunk's lists hold every light (lists off, or before any shadow cube).
  static LightLists all_lights(const GpuScene& scene);

  // Builders: construct, call test_face for each face of each shadow cube as soon as its
  // depth is drawn (viewer/shadow_maps.h), then finish.
  explicit LightLists(const GpuScene& scene);
  // Light `light`'s cube centred at `point`, face `face` (frustum `frustum`) is in the bound
  // depth target with the shadow program bound; `drawn` false if the face was only cleared.
  void test_face(int light, vec3 point, const Frustum& frustum, bool drawn, float near,
                 int resolution);
  // `points`, `start`, `count`: the shadow points (viewer/shadow_maps.h light_start, ...).
  void finish(const GpuScene& scene, const std::vector<vec3>& points, const std::vector<int>& start,
              const std::vector<int>& count);

  GLuint texture() const { return indices_.texture.get(); }
  // Chunk c of mesh m: (first index, count) into the texture's light indices; `shadows`: the
  // list that relies on the shadow cubes (drawn with shadows on), else the emitting-side one.
  const std::vector<glm::ivec2>& ranges(size_t mesh, bool shadows) const {
    return shadows ? shadowed_[mesh] : unshadowed_[mesh];
  }
  int light_at(int index) const { return indices_cpu_.at(size_t(index)); }  // list entry
  int chunk_count() const { return int(boxes_.size()); }
  // Lights a diffuse chunk keeps, mean and max over those chunks, of the shadowed lists.
  double mean_lights() const { return mean_; }
  int max_lights() const { return max_; }
  int queries() const { return queries_issued_; }
  double finish_seconds() const { return finish_seconds_; }  // per-triangle checks, upload

 private:
  // The lists from reach_ (else shadowed_ and unshadowed_ as they are) into the texture.
  void upload(const GpuScene& scene, bool from_reach);
  char& reach(int light, size_t chunk) { return reach_[size_t(light) * boxes_.size() + chunk]; }

  gl::BufferTexture indices_;
  std::vector<int> indices_cpu_;  // the texture's contents
  std::vector<std::vector<glm::ivec2>> shadowed_, unshadowed_;
  // Builder state: per chunk (scene order) its box, mesh and index within the mesh; per light
  // and chunk 0 (term zero: behind the emitter), 1 (in front, not seen yet), 2 (reached).
  std::vector<Bounds> boxes_;
  std::vector<std::pair<size_t, size_t>> chunk_of_;
  std::vector<char> reach_;
  std::vector<char> receives_;  // diffuse: the only meshes that shade direct light
  int light_count_ = 0;
  struct Cluster {
    Bounds bounds;
    std::vector<size_t> chunks;
  };
  std::vector<Cluster> clusters_;
  std::unique_ptr<BoxQueries> queries_;
  int queries_issued_ = 0;
  float margin_ = 0.0f;
  double mean_ = 0.0, finish_seconds_ = 0.0;
  int max_ = 0;
};

}  // namespace lb
