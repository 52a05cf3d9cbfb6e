#pragma once
// A scene uploaded to OpenGL: one vertex array per mesh (position, normal, uv, lightmap uv,
// tangent, vertex radiosity), the textures, the illumination atlas and the light polygons.
// It copies what it needs, so the Scene and BakeResult may go away after construction.

#include <vector>

#include "bake/bake_result.h"
#include "bake/lights.h"
#include "bake/scene.h"
#include "viewer/gl_resources.h"

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
  // Flat meshes (all triangles in one plane): dot(plane.xyz, x) + plane.w = 0, xyz the front
  // normal. Planar mirrors and glossy plates reflect exactly through a mirrored pass.
  bool planar = false;
  glm::vec4 plane{0.0f};
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

class GpuScene {
 public:
  // `bake` may be null: a plain scene, direct light only. Any number of lights: the
  // renderer reads them from buffer textures (viewer/light_table.h).
  GpuScene(const Scene& scene, const BakeResult* bake);

  const Scene& scene() const { return scene_; }  // with radiosity meshes when baked
  const std::vector<GpuMesh>& meshes() const { return meshes_; }
  const GpuLights& lights() const { return lights_; }
  GLuint texture(int index) const;  // 0 for -1 or out of range
  GLuint lightmap() const { return lightmap_.get(); }
  // The bake's soft-light texel map (bake/lightmap/soft_texels.h), 0 without one: drawn in
  // place of the vertex radiosity on meshes with a lightmap.
  GLuint soft_light_map() const { return soft_light_.get(); }
  Bounds bounds() const { return bounds_; }
  bool baked() const { return baked_; }
  // The map holds the direct light too (an export made with `--contents all`): the renderer
  // adds none of its own.
  bool lightmap_holds_direct() const { return lightmap_holds_direct_; }

 private:
  Scene scene_;
  std::vector<GpuMesh> meshes_;
  std::vector<gl::Texture> textures_;
  gl::Texture lightmap_;
  gl::Texture soft_light_;
  GpuLights lights_;
  Bounds bounds_;
  bool baked_ = false;
  bool lightmap_holds_direct_ = false;
};

}  // namespace lb
