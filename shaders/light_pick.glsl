// Direct light whose shadow cost does not grow with the light count: the paper's one shadow
// ray per viewing ray, the light picked in proportion to its contribution, carried into the
// rasteriser. Every light's unshadowed term is exact and cheap (lights.glsl, lamps.glsl); the
// shadow lookups are not. So each fragment sums the unshadowed terms E_i, picks ONE light i
// with probability p_i = Y(E_i) / sum_j Y(E_j) (Y: luminance), and returns
//   E_i * V_i / p_i,
// an unbiased estimate of the shadowed sum sum_j E_j V_j. For lights of one colour
// E_i / p_i is the unshadowed sum itself, so a fully lit fragment is exact in every frame
// and only penumbrae and shadows are noisy. Frames accumulate while the camera rests
// (viewer/renderer.cpp), and the mean converges to the full evaluation of scene.frag.
//
// The pick is one pass over the lights (weighted reservoir sampling with one random number,
// rescaled after each decision), so no array of terms is kept. The random number per pixel
// and frame is a hash of the pixel plus frame * 2^32 / golden ratio (mod 2^32): across the
// frames of a pixel the numbers are a rotated Weyl sequence, evenly spread, so the mean
// converges about as 1/N rather than 1/sqrt(N).
#ifndef LB_LIGHT_PICK_GLSL
#define LB_LIGHT_PICK_GLSL
#include "lights.glsl"
#include "shadows.glsl"
#include "lamps.glsl"
#include "lamp_shadows.glsl"

uniform uint u_frame;  // frames accumulated before this one (viewer/renderer.h)

uint pick_hash(uint x) {
  x ^= x >> 16;
  x *= 0x7feb352du;
  x ^= x >> 15;
  x *= 0x846ca68bu;
  x ^= x >> 16;
  return x;
}

// In [0, 1): 24 bits.
float pixel_random() {
  uvec2 q = uvec2(gl_FragCoord.xy);
  uint h = pick_hash(q.x ^ pick_hash(q.y + 0x9e3779b9u));
  return float((h + u_frame * 0x9e3779b9u) >> 8) * (1.0 / 16777216.0);
}

float pick_weight(vec3 e) { return dot(e, vec3(0.2126, 0.7152, 0.0722)); }

vec3 direct_one_shadow(vec3 p, vec3 n, vec3 ng) {
  float u = pixel_random();
  float total = 0.0;
  int picked = -1;
  vec3 e_picked = vec3(0.0);
  float w_picked = 0.0;
  // Keeps light k with probability w / total; u stays uniform in [0, 1) after each decision.
  for (int i = 0; i < u_light_count; ++i) {
    vec3 e = light_irradiance_over_pi(i, p, n);
    float w = pick_weight(e);
    if (!(w > 0.0)) continue;
    total += w;
    float q = w / total;
    if (u < q) {
      picked = i;
      e_picked = e;
      w_picked = w;
      u = u / q;
    } else {
      u = (u - q) / (1.0 - q);
    }
  }
#if HAS_LAMPS
  for (int i = 0; i < u_lamp_count; ++i) {
    float distance_to_lamp;
    vec3 l = lamp_direction_from(i, p, distance_to_lamp);
    vec3 e = lamp_irradiance_over_pi(i, l, distance_to_lamp, n, ng);
    float w = pick_weight(e);
    if (!(w > 0.0)) continue;
    total += w;
    float q = w / total;
    if (u < q) {
      picked = u_light_count + i;
      e_picked = e;
      w_picked = w;
      u = u / q;
    } else {
      u = (u - q) / (1.0 - q);
    }
  }
#endif
  if (picked < 0) return vec3(0.0);
  vec3 estimate = e_picked * (total / w_picked);
  if (picked < u_light_count) return estimate * light_visibility(picked, p, ng);
#if HAS_LAMPS
  int lamp = picked - u_light_count;
  float distance_to_lamp;
  vec3 l = lamp_direction_from(lamp, p, distance_to_lamp);
  return estimate * lamp_visibility(lamp, p, ng, l, distance_to_lamp);
#else
  return vec3(0.0);
#endif
}

#endif
