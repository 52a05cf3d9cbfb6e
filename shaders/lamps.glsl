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
uniform int u_lamp_kind[MAX_LAMPS];
uniform vec3 u_lamp_position[MAX_LAMPS];   // point, spot: metres
uniform vec3 u_lamp_direction[MAX_LAMPS];  // spot, directional: the way the light travels
uniform vec3 u_lamp_intensity[MAX_LAMPS];  // W/sr (point, spot) or W/m^2 (directional)
uniform float u_lamp_range[MAX_LAMPS];     // metres, 0: unlimited
uniform float u_lamp_cos_inner[MAX_LAMPS];
uniform float u_lamp_cos_outer[MAX_LAMPS];

// Unit direction from p towards lamp i and the distance to it (a large number at infinity).
vec3 lamp_direction_from(int i, vec3 p, out float distance_to_lamp) {
  if (u_lamp_kind[i] == LAMP_DIRECTIONAL) {
    distance_to_lamp = 1e30;
    return -u_lamp_direction[i];
  }
  vec3 d = u_lamp_position[i] - p;
  distance_to_lamp = length(d);
  return d / max(distance_to_lamp, 1e-20);
}

// lb::spot_falloff: 1 inside the inner cone, 0 outside the outer, the square of a linear ramp
// in cos(angle) between.
float lamp_spot_falloff(int i, float cos_angle) {
  if (u_lamp_kind[i] != LAMP_SPOT) return 1.0;
  float scale = 1.0 / max(0.001, u_lamp_cos_inner[i] - u_lamp_cos_outer[i]);
  float t = clamp((cos_angle - u_lamp_cos_outer[i]) * scale, 0.0, 1.0);
  return t * t;
}

// lb::range_window: clamp(1 - (d / range)^4, 0, 1)^2, 1 without a range.
float lamp_range_window(int i, float distance_to_lamp) {
  float range = u_lamp_range[i];
  if (!(range > 0.0) || u_lamp_kind[i] == LAMP_DIRECTIONAL) return 1.0;
  float r = distance_to_lamp / range;
  float w = clamp(1.0 - r * r * r * r, 0.0, 1.0);
  return w * w;
}

// E / pi from lamp i at p with shading normal n (bumped) and geometric normal ng; `l` and
// `distance_to_lamp` from lamp_direction_from. No light reaches the back of the surface.
vec3 lamp_irradiance_over_pi(int i, vec3 l, float distance_to_lamp, vec3 n, vec3 ng) {
  float cos_theta = dot(n, l);
  if (cos_theta <= 0.0 || dot(ng, l) <= 0.0) return vec3(0.0);
  if (u_lamp_kind[i] == LAMP_DIRECTIONAL) return u_lamp_intensity[i] * (cos_theta / PI);
  float falloff = lamp_spot_falloff(i, dot(-l, u_lamp_direction[i]));
  float window = lamp_range_window(i, distance_to_lamp);
  return u_lamp_intensity[i] *
         (falloff * window * cos_theta / (PI * distance_to_lamp * distance_to_lamp));
}

#endif
