// Hard shadows of lamps (viewer/lamp_shadow_maps.h): a depth cube per point lamp (and per spot
// wider than the perspective map takes), a perspective map per spot, an orthographic map over
// the scene's bounds per directional lamp, all layers of one depth texture array.
//
// A lamp is a point, so there is no penumbra to find: one depth test, filtered with four
// bilinear 2x2 PCF taps half a texel apart (a 3x3-texel tent), which smooths the texel steps of
// the edge. The normal offset against acne is the area lights' (shaders/shadows.glsl): one and
// a half texels, growing to four and a half where the light grazes the surface.
#ifndef LB_LAMP_SHADOWS_GLSL
#define LB_LAMP_SHADOWS_GLSL
#include "shadows.glsl"

uniform sampler2DArrayShadow u_lamp_shadow_maps;
uniform int u_lamp_shadow_resolution;
uniform int u_lamp_shadow_layer[MAX_LAMPS];   // first layer, -1: no shadow map
uniform int u_lamp_shadow_cube[MAX_LAMPS];    // 1: six cube faces around the lamp
uniform mat4 u_lamp_shadow_matrix[MAX_LAMPS];  // world -> clip, spot and directional maps
uniform vec2 u_lamp_shadow_range[MAX_LAMPS];  // cube near and far planes, metres
// A shadow texel's footprint in metres at distance d from the lamp: x * d + y.
uniform vec2 u_lamp_shadow_texel[MAX_LAMPS];

// Fraction of lamp i that p (geometric normal ng) sees, in [0, 1]; l is the unit direction
// from p to the lamp, distance_to_lamp its distance (lamp_direction_from in lamps.glsl).
float lamp_visibility(int i, vec3 p, vec3 ng, vec3 l, float distance_to_lamp) {
  int layer = u_lamp_shadow_layer[i];
  if (layer < 0) return 1.0;
  // Directional lamps have x = 0 (and distance 1e30): a constant footprint.
  float texel = u_lamp_shadow_texel[i].x * distance_to_lamp + u_lamp_shadow_texel[i].y;
  float grazing = 1.0 - clamp(dot(ng, l), 0.0, 1.0);
  vec3 q = p + ng * ((1.5 + 3.0 * grazing) * texel);
  vec4 clip;
  if (u_lamp_shadow_cube[i] != 0) {
    vec3 offset = q - u_lamp_position[i];
    int face = cube_face_of(offset);
    clip = cube_face_clip_range(offset, face, u_lamp_shadow_range[i].x, u_lamp_shadow_range[i].y);
    layer += face;
  } else {
    clip = u_lamp_shadow_matrix[i] * vec4(q, 1.0);
  }
  vec3 ndc = clip.xyz / clip.w;
  // Outside a spot's map is outside its cone; outside the directional map, outside the scene.
  if (clip.w <= 0.0 || abs(ndc.x) > 1.0 || abs(ndc.y) > 1.0) return 1.0;
  vec2 uv = 0.5 * ndc.xy + 0.5;
  float depth = min(0.5 * ndc.z + 0.5, 1.0);
  float h = 0.5 / float(u_lamp_shadow_resolution);
  float sum = texture(u_lamp_shadow_maps, vec4(uv + vec2(-h, -h), float(layer), depth)) +
              texture(u_lamp_shadow_maps, vec4(uv + vec2(h, -h), float(layer), depth)) +
              texture(u_lamp_shadow_maps, vec4(uv + vec2(-h, h), float(layer), depth)) +
              texture(u_lamp_shadow_maps, vec4(uv + vec2(h, h), float(layer), depth));
  return 0.25 * sum;
}

#endif
