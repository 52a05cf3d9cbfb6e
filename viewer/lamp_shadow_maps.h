#pragma once
// Shadow maps of the lamps (point, spot, directional; bake/scene.h), rendered once per scene
// into one depth texture array: six cube faces around a point lamp (and a spot wider than
// kMaxSpotMapHalfAngle), one perspective map along a spot's axis covering its outer cone, one
// orthographic map along a directional lamp covering the scene's bounding sphere. The lookup
// is in shaders/lamp_shadows.glsl.
//
// At most kMaxShadowedLamps lamps (the first ones in the scene with any intensity) get a map;
// the others light the scene unshadowed, with one warning on stderr.

#include <glm/glm.hpp>
#include <vector>

#include "viewer/alpha_cut.h"
#include "viewer/gpu_scene.h"
#include "viewer/render_settings.h"
#include "viewer/shader_program.h"

namespace lb {

constexpr int kMaxShadowedLamps = 8;
// Spots up to this half-angle (radians, 60 degrees) get a perspective map, wider ones a cube.
constexpr float kMaxSpotMapHalfAngle = 1.0471976f;

// One lamp's map, as shaders/lamp_shadows.glsl reads it.
struct LampShadow {
  int layer = -1;          // first layer in the array; -1: no map
  bool cube = false;       // six layers, faces as cube_face_clip_range (shaders/shadows.glsl)
  glm::mat4 matrix{1.0f};  // world -> clip (perspective or orthographic maps)
  glm::vec2 range{0.0f};   // cube near and far planes, metres
  glm::vec2 texel{0.0f};   // texel footprint in metres at distance d: x * d + y
};

class LampShadowMaps {
 public:
  LampShadowMaps() = default;
  // `programs` are the shadow pass (shaders/shadow.vert + shadow.frag, and its ALPHA_CUT
  // variant: viewer/alpha_cut.h).
  LampShadowMaps(const GpuScene& scene, const DepthPrograms& programs,
                 const ShadowSettings& settings);

  GLuint depth_array() const { return depth_.get(); }
  int resolution() const { return resolution_; }
  // One per lamp of the scene, in order.
  const std::vector<LampShadow>& lamps() const { return lamps_; }
  int layer_count() const { return layers_; }
  int unshadowed_count() const { return unshadowed_; }  // lamps beyond kMaxShadowedLamps

 private:
  gl::Texture depth_;
  std::vector<LampShadow> lamps_;
  int resolution_ = 0;
  int layers_ = 0;
  int unshadowed_ = 0;
};

}  // namespace lb
