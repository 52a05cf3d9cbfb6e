#pragma once
// The per-light data the scene shader reads, as two buffer textures (samplerBuffer), so the
// light count has no cap (uniform arrays held 32 area lights and 16 lamps). The texel layout
// is the contract with shaders/lights.glsl, shadows.glsl, lamps.glsl and lamp_shadows.glsl.
//
// Area light i, RGBA32F texels 4i .. 4i+3:
//   (radiance W/(sr m^2) rgb, outline start or -1), (triangle start, triangle count,
//    first shadow cube, shadow cube count), (centroid m, bounding radius about it m),
//   (unit normal for a flat light or 0 for others, luminance of the radiance times the
//    area, W/sr)
// Lamp i, texels kLampTexels * i + 0..8:
//   (position m, kind), (unit direction the light travels, range m or 0),
//   (intensity W/sr or W/m^2, cos inner cone), (cos outer cone, shadow layer or -1,
//    cube 0/1, 0), (cube near, cube far m, texel footprint x, y), shadow matrix columns 0..3
// Integers are stored as floats: exact below 2^24.

#include <vector>

#include "viewer/gl_resources.h"
#include "viewer/gpu_scene.h"
#include "viewer/lamp_shadow_maps.h"
#include "viewer/shadow_maps.h"

namespace lb {

constexpr int kLightTexels = 5;
constexpr int kLampTexels = 9;

struct LightTable {
  gl::BufferTexture lights;  // area lights
  gl::BufferTexture lamps;
  int light_count = 0;
  int lamp_count = 0;
};

// `lamp_shadows` may know fewer lamps than the scene (update_scene keeps the maps): the
// others go unshadowed.
LightTable make_light_table(const GpuScene& scene, const ShadowMaps& shadows,
                            const LampShadowMaps& lamp_shadows);

}  // namespace lb
