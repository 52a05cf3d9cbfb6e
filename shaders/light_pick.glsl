// Direct light whose cost does not grow with the light count: the paper's one shadow ray per
// viewing ray, the light picked in proportion to its contribution, carried into the
// rasteriser. Each fragment gives every light a cheap weight w_i (below), picks ONE light i
// with probability p_i = w_i / W (W = sum w_j), evaluates only that light's exact unshadowed
// term E_i (Lambert's closed form, lights.glsl; lamps.glsl) and its shadow lookups V_i
// (shadows.glsl, lamp_shadows.glsl; of an area light's K shadow points, one, picked with the
// same random number), and returns
//   E_i * V_i / p_i,
// an unbiased estimate of the full sum sum_j E_j V_j of scene.frag's exact path wherever
// w_j > 0 when E_j > 0 (the weights make sure of that). Frames accumulate while the camera
// rests (viewer/renderer.cpp) and their mean converges to the full evaluation. Measured on
// llvmpipe the exact polygon terms, not the shadow lookups, were the bulk of the cost: picking
// only the shadows (all exact terms, one light's lookups) made Figure 5's frame 1.4x faster,
// this 5x (docs/viewer.md).
//
// The weight of an area light is the luminance of its point-light estimate of E/pi,
// Y(L) A cos cos' / (pi r^2), with two guards that keep it positive wherever the exact term
// is: the receiver's cosine is taken to the centroid moved by the light's bounding radius
// rho towards the horizon (some part may still be above it), and r^2 becomes r^2 + rho^2 (so
// it stays finite on the light). Flat lights add the emitter's cosine (exactly 0 behind the
// plane). Two texel fetches and no square root per light. A lamp's weight is its exact
// unshadowed term, which is already cheap.
//
// The pick inverts the weights' running sum with one random number per pixel and frame: a
// hash of the pixel plus frame * 2^32 / golden ratio (mod 2^32). Across the frames of a pixel
// the numbers are a rotated Weyl sequence, evenly spread over [0, 1), and each light owns one
// interval of it, so after N frames light i has been picked N p_i times to within one, and
// the mean converges about as 1/N rather than 1/sqrt(N).
#ifndef LB_LIGHT_PICK_GLSL
#define LB_LIGHT_PICK_GLSL
#include "lights.glsl"
#include "shadows.glsl"
#include "lamps.glsl"
#include "lamp_shadows.glsl"
#include "hash.glsl"

uniform uint u_frame;  // frames accumulated before this one (viewer/renderer.h)

// In [0, 1): 24 bits.
float pixel_random() {
  uvec2 q = uvec2(gl_FragCoord.xy);
  uint h = hash_uint(q.x ^ hash_uint(q.y + 0x9e3779b9u));
  return float((h + u_frame * 0x9e3779b9u) >> 8) * (1.0 / 16777216.0);
}

float pick_luminance(vec3 e) { return dot(e, vec3(0.2126, 0.7152, 0.0722)); }

float light_pick_weight(int i, vec3 p, vec3 n) {
  vec4 sphere = texelFetch(u_light_data, LIGHT_TEXELS * i + 2);
  vec4 plane = texelFetch(u_light_data, LIGHT_TEXELS * i + 3);
  vec3 d = sphere.xyz - p;
  float r2 = dot(d, d);
  float inv_r = inversesqrt(r2);
  float cos_receiver = clamp((dot(n, d) + sphere.w) * inv_r, 0.0, 1.0);
  float cos_emitter = dot(plane.xyz, plane.xyz) > 0.0 ? max(dot(plane.xyz, -d), 0.0) * inv_r : 1.0;
  return plane.w * cos_receiver * cos_emitter / (PI * (r2 + sphere.w * sphere.w));
}

float lamp_pick_weight(int i, vec3 p, vec3 n, vec3 ng) {
  float distance_to_lamp;
  vec3 l = lamp_direction_from(i, p, distance_to_lamp);
  return pick_luminance(lamp_irradiance_over_pi(i, l, distance_to_lamp, n, ng));
}

vec3 direct_one_light(vec3 p, vec3 n, vec3 ng) {
  float total = 0.0;
  // Over this chunk's light list (lights.glsl): the lights left out add nothing, so the
  // estimate stays unbiased and the others are picked more often.
  for (int j = 0; j < u_light_range.y; ++j) total += light_pick_weight(listed_light(j), p, n);
#if HAS_LAMPS
  for (int i = 0; i < u_lamp_count; ++i) total += lamp_pick_weight(i, p, n, ng);
#endif
  if (!(total > 0.0)) return vec3(0.0);
  // The light whose interval of the running sum holds u * total; the last one with any
  // weight if rounding leaves u * total beyond the sum.
  float target = pixel_random() * total;
  float running = 0.0;
  int picked = -1;
  float weight = 0.0, start = 0.0;
  for (int j = 0; j < u_light_range.y && running <= target; ++j) {
    int i = listed_light(j);
    float w = light_pick_weight(i, p, n);
    if (w > 0.0) picked = i, weight = w, start = running;
    running += w;
  }
#if HAS_LAMPS
  for (int i = 0; i < u_lamp_count && running <= target; ++i) {
    float w = lamp_pick_weight(i, p, n, ng);
    if (w > 0.0) picked = u_light_count + i, weight = w, start = running;
    running += w;
  }
#endif
  if (picked < 0) return vec3(0.0);
  float inverse_p = total / weight;
  if (picked < u_light_count) {
    vec3 e = light_irradiance_over_pi(picked, p, n);
#if USE_SHADOWS
    // Where u fell inside the light's interval is again uniform in [0, 1): it picks the
    // shadow point.
    float u = clamp((target - start) / weight, 0.0, 1.0);
    if (max(e.r, max(e.g, e.b)) > 0.0) e *= light_visibility_one(picked, p, ng, u);
#endif
    return e * inverse_p;
  }
#if HAS_LAMPS
  int lamp = picked - u_light_count;
  float distance_to_lamp;
  vec3 l = lamp_direction_from(lamp, p, distance_to_lamp);
  vec3 e = lamp_irradiance_over_pi(lamp, l, distance_to_lamp, n, ng);
#if USE_SHADOWS
  if (max(e.r, max(e.g, e.b)) > 0.0) e *= lamp_visibility(lamp, p, ng, l, distance_to_lamp);
#endif
  return e * inverse_p;
#else
  return vec3(0.0);
#endif
}

#endif
