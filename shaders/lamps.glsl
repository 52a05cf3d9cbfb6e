// Direct light from lamps (point, spot, directional; bake/scene.h), unoccluded.
//
// A point or spot lamp of radiant intensity I (W/sr) at distance d gives a surface whose
// normal makes angle theta with the way to the lamp the irradiance
//   E = I * spot_falloff * range_window(d) * cos(theta) / d^2,
// a directional lamp of irradiance E0 (W/m^2 facing it) E = E0 * cos(theta). The falloff and
// the window mirror lb::spot_falloff and lb::range_window (bake/light_sources.cpp) term for
// term: glTF's KHR_lights_punctual recommendations. Returned as E / pi, the stored-light
// convention of the area lights (shaders/lights.glsl, bake/bake_result.h).
#ifndef LB_LAMPS_GLSL
#define LB_LAMPS_GLSL
#include "common.glsl"

const int LAMP_POINT = 0;  // lb::LampKind
const int LAMP_SPOT = 1;
const int LAMP_DIRECTIONAL = 2;

uniform int u_lamp_count;
// Per lamp, LAMP_TEXELS RGBA32F texels (viewer/light_table.h).
uniform samplerBuffer u_lamp_data;
const int LAMP_TEXELS = 9;

vec4 lamp_texel(int i, int k) { return texelFetch(u_lamp_data, LAMP_TEXELS * i + k); }
int lamp_kind(int i) { return int(lamp_texel(i, 0).w); }
vec3 lamp_position(int i) { return lamp_texel(i, 0).xyz; }        // point, spot: metres
vec3 lamp_direction(int i) { return lamp_texel(i, 1).xyz; }       // the way the light travels
vec3 lamp_intensity(int i) { return lamp_texel(i, 2).rgb; }  // W/sr (point, spot), W/m^2 (dir.)

// Unit direction from p towards lamp i and the distance to it (a large number at infinity).
vec3 lamp_direction_from(int i, vec3 p, out float distance_to_lamp) {
  vec4 position_kind = lamp_texel(i, 0);
  if (int(position_kind.w) == LAMP_DIRECTIONAL) {
    distance_to_lamp = 1e30;
    return -lamp_direction(i);
  }
  vec3 d = position_kind.xyz - p;
  distance_to_lamp = length(d);
  return d / max(distance_to_lamp, 1e-20);
}

// lb::spot_falloff: 1 inside the inner cone, 0 outside the outer, the square of a linear ramp
// in cos(angle) between.
float lamp_spot_falloff(int i, float cos_angle) {
  if (lamp_kind(i) != LAMP_SPOT) return 1.0;
  float cos_inner = lamp_texel(i, 2).w, cos_outer = lamp_texel(i, 3).x;
  float scale = 1.0 / max(0.001, cos_inner - cos_outer);
  float t = clamp((cos_angle - cos_outer) * scale, 0.0, 1.0);
  return t * t;
}

// lb::range_window: clamp(1 - (d / range)^4, 0, 1)^2, 1 without a range.
float lamp_range_window(int i, float distance_to_lamp) {
  float range = lamp_texel(i, 1).w;  // metres, 0: unlimited
  if (!(range > 0.0) || lamp_kind(i) == LAMP_DIRECTIONAL) return 1.0;
  float r = distance_to_lamp / range;
  float w = clamp(1.0 - r * r * r * r, 0.0, 1.0);
  return w * w;
}

// E / pi from lamp i at p with shading normal n (bumped) and geometric normal ng; `l` and
// `distance_to_lamp` from lamp_direction_from. No light reaches the back of the surface.
vec3 lamp_irradiance_over_pi(int i, vec3 l, float distance_to_lamp, vec3 n, vec3 ng) {
  float cos_theta = dot(n, l);
  if (cos_theta <= 0.0 || dot(ng, l) <= 0.0) return vec3(0.0);
  if (lamp_kind(i) == LAMP_DIRECTIONAL) return lamp_intensity(i) * (cos_theta / PI);
  float falloff = lamp_spot_falloff(i, dot(-l, lamp_direction(i)));
  float window = lamp_range_window(i, distance_to_lamp);
  return lamp_intensity(i) *
         (falloff * window * cos_theta / (PI * distance_to_lamp * distance_to_lamp));
}

#endif
