#pragma once
// Soft-shadow depth cubes: K points on each light, one depth cube per point, rendered once
// per scene (lights and geometry are static) into one depth texture array. The lookup and
// its reasoning are in shaders/shadows.glsl.

#include <limits>
#include <vector>

#include "viewer/alpha_cut.h"
#include "viewer/gpu_scene.h"
#include "viewer/light_lists.h"
#include "viewer/render_settings.h"
#include "viewer/shader_program.h"

namespace lb {

class ShadowMaps {
 public:
  ShadowMaps() = default;
  // Renders all cubes; `programs` are the shadow pass (shaders/shadow.vert + shadow.frag, and
  // its ALPHA_CUT variant: viewer/alpha_cut.h).
  // With `lists`, each face's depth also answers its occlusion queries as soon as it is drawn
  // (viewer/light_lists.h), and the lists are finished.
  ShadowMaps(const GpuScene& scene, const DepthPrograms& programs,
             const ShadowSettings& settings, LightLists* lists = nullptr);
  // Renders them again from other points (another interleaved set), into the same texture
  // when its size still fits.
  void rebuild(const GpuScene& scene, const DepthPrograms& programs,
               const ShadowSettings& settings, LightLists* lists = nullptr);

  GLuint depth_array() const { return depth_.get(); }
  GLuint points_texture() const { return points_.texture.get(); }
  const std::vector<int>& light_start() const { return start_; }
  const std::vector<int>& light_count() const { return count_; }
  int resolution() const { return resolution_; }
  float near_plane() const { return near_; }
  float far_plane() const { return far_; }
  int cube_count() const { return int(points_count_); }
  const DrawCounts& draw_counts() const { return counts_; }  // of the last (re)build

 private:
  gl::Texture depth_;
  gl::BufferTexture points_;
  size_t points_count_ = 0;
  std::vector<int> start_, count_;
  int resolution_ = 0;
  int layers_ = 0, depth_resolution_ = 0;  // of depth_ as allocated
  float near_ = 0.01f, far_ = 1.0f;
  DrawCounts counts_;
};

// K for a scene with `light_count` lights. The automatic K also keeps the cubes' 6 K lights
// faces within `max_layers` (one depth texture array's limit, max_shadow_layers()), down to one
// point a light, so a level with many lights gets harder shadows rather than none.
int shadow_samples_per_light(const ShadowSettings& settings, size_t light_count,
                             int max_layers = std::numeric_limits<int>::max());
// GL_MAX_ARRAY_TEXTURE_LAYERS of the current context.
int max_shadow_layers();

// Shared by the shadow passes (area lights here, lamps in viewer/lamp_shadow_maps.h).
// A depth texture array for sampler2DArrayShadow lookups (bilinear PCF, LEQUAL).
gl::Texture make_depth_array(int resolution, int layers);
// Binds a new depth-only framebuffer (returned: keep it alive) and sets the pass's state.
gl::Framebuffer begin_shadow_pass(int resolution);
// Every mesh that casts shadows (emitters do not) and that `frustum` may see (the map's own:
// a cube face's or a lamp's matrix), the alpha-cut ones with their program; adds what it drew
// to `counts`. `programs.opaque` is bound before and after.
void draw_shadow_casters(const GpuScene& scene, const DepthPrograms& programs,
                         const Frustum& frustum, DrawCounts& counts);
void end_shadow_pass();

}  // namespace lb
