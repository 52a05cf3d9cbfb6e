// Hard shadows of lamps (viewer/lamp_shadow_maps.h): a depth cube per point lamp (and per spot
// wider than the perspective map takes), a perspective map per spot, an orthographic map over
// the scene's bounds per directional lamp, all layers of one depth texture array.
//
// A lamp is a point, so there is no penumbra to find: one depth test, filtered with four
// bilinear 2x2 PCF taps half a texel apart (a 3x3-texel tent), which smooths the texel steps of
// the edge. The normal offset against acne: one and a half texels, growing to four and a half
// where the light grazes the surface (the area lights' lookup in shaders/shadows.glsl now uses
// half a texel; lamps were not measured, so they keep this).
#ifndef LB_LAMP_SHADOWS_GLSL
#define LB_LAMP_SHADOWS_GLSL
#include "shadows.glsl"
#include "lamps.glsl"

uniform sampler2DArrayShadow u_lamp_shadow_maps;
uniform int u_lamp_shadow_resolution;
// Per lamp in u_lamp_data (lamps.glsl, viewer/light_table.h): texel 3 .y the first layer
// (-1: no shadow map), .z 1 for six cube faces around the lamp; texel 4 the cube's near and
// far planes (metres) and a shadow texel's footprint in metres at distance d from the lamp,
// zw.x * d + zw.y; texels 5..8 the world -> clip matrix of spot and directional maps.

// Fraction of lamp i that p (geometric normal ng) sees, in [0, 1]; l is the unit direction
// from p to the lamp, distance_to_lamp its distance (lamp_direction_from in lamps.glsl).
float lamp_visibility(int i, vec3 p, vec3 ng, vec3 l, float distance_to_lamp) {
  vec4 map = lamp_texel(i, 3);
  int layer = int(map.y);
  if (layer < 0) return 1.0;
  vec4 range_texel = lamp_texel(i, 4);
  // Directional lamps have x = 0 (and distance 1e30): a constant footprint.
  float texel = range_texel.z * distance_to_lamp + range_texel.w;
  float grazing = 1.0 - clamp(dot(ng, l), 0.0, 1.0);
  vec3 q = p + ng * ((1.5 + 3.0 * grazing) * texel);
  vec4 clip;
  if (map.z != 0.0) {
    vec3 offset = q - lamp_position(i);
    int face = cube_face_of(offset);
    clip = cube_face_clip_range(offset, face, range_texel.x, range_texel.y);
    layer += face;
  } else {
    mat4 matrix = mat4(lamp_texel(i, 5), lamp_texel(i, 6), lamp_texel(i, 7), lamp_texel(i, 8));
    clip = matrix * vec4(q, 1.0);
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
