#pragma once
// A scene uploaded to OpenGL: one vertex array per mesh (position, normal, uv, lightmap uv,
// tangent, vertex radiosity) with its triangles in spatial chunks for culling, the textures,
// the illumination atlas and the light polygons.
// It copies what it needs, so the Scene and BakeResult may go away after construction.

#include <array>
#include <vector>

#include "bake/bake_result.h"
#include "bake/lights.h"
#include "bake/probe_grid.h"
#include "bake/scene.h"
#include "viewer/frustum.h"
#include "viewer/gl_resources.h"
#include "viewer/mesh_chunks.h"
#include "viewer/mesh_detail.h"

namespace lb {

struct GpuMesh {
  gl::VertexArray vertex_array;
  gl::Buffer vertices;
  gl::Buffer indices;
  GLsizei index_count = 0;
  int material = 0;
  bool has_normals = false;
  bool has_lightmap = false;
  bool has_vertex_radiance = false;
  bool has_patches = false;
  gl::BufferTexture triangle_patch;  // R32UI per triangle, radiosity patch id
  Bounds bounds;
  // Spatial chunks (viewer/mesh_chunks.h): the index buffer holds the triangles in chunk
  // order, and so does triangle_patch; one chunk in the mesh's own order when small.
  std::vector<MeshChunk> chunks;
  // Per chunk, its coarser levels (viewer/mesh_detail.h), finer to coarser, their triangles
  // after the mesh's own in the index buffer (first_triangle counts from the buffer's start);
  // triangle_patch holds their patch ids there too.
  std::vector<std::vector<DetailLevel>> chunk_levels;
  // Flat meshes (all triangles in one plane): dot(plane.xyz, x) + plane.w = 0, xyz the front
  // normal. Planar mirrors and glossy plates reflect exactly through a mirrored pass.
  bool planar = false;
  glm::vec4 plane{0.0f};
  // A moving object (Scene::dynamic_meshes): its baked light from the light probes, none from
  // the bake: the blends at its vertices as its vertex radiance where known, and probe_sh, the
  // blend at its centre (bake/probe_grid.h's radiance SH), for a bump's detail or alone.
  bool probe_lit = false;
  ShL2 probe_sh{};
};

struct GpuLights {
  std::vector<AreaLight> lights;
  gl::BufferTexture triangles;  // 3 RGB32F texels (world corners) per emitting triangle
  std::vector<int> triangle_start, triangle_count;
  // Lights made of two triangles sharing an edge (quads) also as their 4-corner outline:
  // when the whole quad is above a point's horizon the shader sums 4 edges instead of 6.
  gl::BufferTexture outlines;      // 4 RGB32F texels per quad light
  std::vector<int> outline_start;  // texel index / 4, or -1
};

// What the culled draws of a pass drew (viewer/frustum.h): chunks and triangles drawn of all.
struct DrawCounts {
  int chunks_drawn = 0, chunks_total = 0;
  size_t triangles_drawn = 0, triangles_total = 0;
  int draw_calls = 0;
  int chunks_simplified = 0;  // of chunks_drawn, drawn at a coarser level (viewer/mesh_detail.h)
  void add(const DrawCounts& other);
};

class GpuScene {
 public:
  // `bake` may be null: a plain scene, direct light only. Any number of lights: the
  // renderer reads them from buffer textures (viewer/light_table.h). The scene's moving
  // objects come after its meshes, probe-lit when there is a bake (light probes baked here,
  // bake/probes/dynamic_light.h), else lit as the rest.
  GpuScene(const Scene& scene, const BakeResult* bake);

  const Scene& scene() const { return scene_; }  // with radiosity meshes when baked
  const std::vector<GpuMesh>& meshes() const { return meshes_; }
  const GpuLights& lights() const { return lights_; }
  GLuint texture(int index) const;  // 0 for -1 or out of range
  GLuint lightmap() const { return lightmap_.get(); }
  // The bake's soft-light texel map (bake/lightmap/soft_texels.h), 0 without one: drawn in
  // place of the vertex radiosity on meshes with a lightmap.
  GLuint soft_light_map() const { return soft_light_.get(); }
  // The lightmap's L1 band per world axis (IlluminationMaps::l1), 0 without one.
  GLuint lightmap_l1(int axis) const { return lightmap_l1_[size_t(axis)].get(); }
  // The soft-light map's L1 band per world axis (SoftTexelMap::l1), 0 without one.
  GLuint soft_light_l1(int axis) const { return soft_light_l1_[size_t(axis)].get(); }
  Bounds bounds() const { return bounds_; }
  bool baked() const { return baked_; }
  // The map holds the direct light too (an export made with `--contents all`): the renderer
  // adds none of its own.
  bool lightmap_holds_direct() const { return lightmap_holds_direct_; }

  // Draws mesh `m`'s chunks that `frustum` may see, with its vertex array bound and the
  // current program; runs of adjacent visible chunks go in one call. `first_triangle_uniform`
  // (of the current program, -1 for none) receives each call's first triangle in the mesh, so
  // gl_PrimitiveID + it indexes per-triangle data. With culling off it draws every chunk, in
  // one call as before chunks existed. With `light_ranges` (one per chunk, viewer/light_lists.h)
  // a run also ends where the chunk's range changes, and `light_range_uniform` (an ivec2)
  // receives each call's. With an active `detail` each chunk is drawn at the coarsest level
  // it accepts (viewer/mesh_detail.h), whether culling is on or off, and
  // `detail_lift_uniform` (a float) receives each call's level error (0 at full detail).
  void draw_mesh(size_t m, const Frustum& frustum, DrawCounts& counts,
                 const DetailView& detail = {}, GLint first_triangle_uniform = -1,
                 const std::vector<glm::ivec2>* light_ranges = nullptr,
                 GLint light_range_uniform = -1, GLint detail_lift_uniform = -1) const;
  // Whether mesh `m` lies wholly outside `frustum` (culling on): then it counts the mesh as
  // skipped, and the caller need not prepare its draw.
  bool culled(size_t m, const Frustum& frustum, DrawCounts& counts) const;
  // Counts mesh `m` as skipped (of all, none drawn).
  void count_skipped(size_t m, DrawCounts& counts) const;
  void set_culling(bool on) { culling_ = on; }
  // Whether depth-only passes test boxes against the depth drawn (viewer/occlusion_culler.h).
  void set_occlusion_culling(bool on) { occlusion_ = on; }
  bool occlusion_culling() const { return occlusion_; }
  // Bytes of the meshes' vertex, index and patch buffers (GPU-side geometry memory).
  size_t geometry_bytes() const { return geometry_bytes_; }
  // Triangles of every level of detail together (their share of geometry_bytes).
  size_t detail_triangles() const { return detail_triangles_; }
  bool culling() const { return culling_; }

 private:
  // Appends the scene's moving objects to meshes_ and scene_.meshes.
  void add_dynamic_meshes(const Scene& scene, const BakeResult* bake);

  Scene scene_;
  std::vector<GpuMesh> meshes_;
  std::vector<gl::Texture> textures_;
  gl::Texture lightmap_;
  gl::Texture soft_light_;
  std::array<gl::Texture, 3> lightmap_l1_;
  std::array<gl::Texture, 3> soft_light_l1_;
  GpuLights lights_;
  Bounds bounds_;
  bool baked_ = false;
  bool lightmap_holds_direct_ = false;
  bool culling_ = true;
  bool occlusion_ = true;
  size_t geometry_bytes_ = 0;
  size_t detail_triangles_ = 0;
};

}  // namespace lb
