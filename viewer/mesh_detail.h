#pragma once
// Levels of detail for the viewer: coarser copies of each mesh chunk's triangles
// (viewer/mesh_chunks.h) for views where the chunk covers few pixels.
//
// A level is made by half-edge collapses (OpenMesh's decimater: Garland and Heckbert's quadric
// error orders them, a Hausdorff test bounds them), so its triangles index a subset of the
// chunk's own vertices: normals, uvs, lightmap uvs and vertex radiance stay each vertex's own
// and the level shares the mesh's vertex buffer.
// Vertices on the chunk's boundary stay where they are: that boundary holds the cuts between
// chunks and every seam where the vertex buffer splits a vertex (hard edges, uv and lightmap
// chart seams), so chunks drawn at different levels meet without cracks and no simplified
// triangle spans two lightmap charts.

#include <cstdint>
#include <vector>

#include "bake/scene.h"
#include "viewer/mesh_chunks.h"

namespace lb {

struct DetailLevel {
  uint32_t first_triangle = 0;  // into MeshDetail::triangles
  uint32_t triangle_count = 0;
  // Metres: no vertex of the chunk lies farther than this from the level's triangles (the
  // one-sided Hausdorff distance from the full chunk's vertices, OpenMesh's ModHausdorffT).
  float error = 0.0f;
};

struct MeshDetail {
  std::vector<uvec3> triangles;  // every chunk's levels, one after another
  std::vector<uint32_t> source;  // per triangle: the mesh triangle it is (patch ids)
  // Per chunk, finer to coarser; the chunk itself (error 0) is not among them. Empty for
  // chunks too small or too flat to simplify.
  std::vector<std::vector<DetailLevel>> chunk_levels;
};

// Chunks of fewer triangles than this keep full detail only.
constexpr uint32_t kMinDetailTriangles = 64;

// Deterministic: the same mesh and chunks give the same levels.
MeshDetail make_mesh_detail(const Mesh& mesh, const MeshChunks& chunks);

// Every mesh's levels, on every core. A mesh congruent to an earlier one (an instance of the
// same furniture: the same triangles and chunks, every edge the same length to rounding) takes
// that one's levels, which hold for it too (the Hausdorff distance is kept by rigid motions and
// mirroring); a level of many instances is simplified once.
std::vector<MeshDetail> make_scene_detail(const std::vector<Mesh>& meshes,
                                          const std::vector<MeshChunks>& chunks);

// How much geometric error a camera pass accepts: a chunk may be drawn at a level whose error,
// seen from `eye` at the chunk's nearest point, spans at most `max_pixels` pixels.
struct DetailView {
  vec3 eye{0.0f};
  float pixels_per_radian = 0.0f;  // the image's height / (2 tan(fov / 2)), near its centre
  float max_pixels = 0.0f;         // 0: full detail everywhere
  bool active() const { return max_pixels > 0.0f && pixels_per_radian > 0.0f; }
};

// A camera pass's view from its world-to-clip matrix (a perspective projection times a rigid
// or mirrored view, jittered or not) and its image height in pixels.
DetailView make_detail_view(const glm::mat4& world_to_clip, vec3 eye, int image_height,
                            float max_pixels);

// The coarsest of `levels` that `view` accepts for a chunk with `bounds`; -1 for full detail.
int pick_detail_level(const std::vector<DetailLevel>& levels, const Bounds& bounds,
                      const DetailView& view);

}  // namespace lb
