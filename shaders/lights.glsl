// Direct light from polygonal Lambertian emitters, exactly (no shadows here).
//
// Lambert's closed form (1760) for the irradiance at a point p with normal n from a polygon of
// constant radiance L:   E = L * sum_i 0.5 * theta_i * dot(n, gamma_i),
// theta_i the angle the edge (v_i, v_i+1) subtends at p and gamma_i the unit normal of the
// plane through p and that edge. It holds only for the part of the polygon above the horizon
// of n, so each light triangle is first clipped by the plane dot(n, x - p) = 0. Unlike Eq. 2
// of the paper (a point approximation), it stays exact next to the light.
//
// The stored-light convention (bake/bake_result.h) is E / pi, so everything here returns
// E / pi = L * |sum_i theta_i dot(n, gamma_i)| / (2 pi).
#ifndef LB_LIGHTS_GLSL
#define LB_LIGHTS_GLSL
#include "common.glsl"

// Light triangles: 3 RGB32F texels per triangle (world-space corners, emitting side CCW).
uniform samplerBuffer u_light_triangles;
uniform int u_light_count;
// The lights that can reach this draw's chunk (viewer/light_lists.h): light indices
// u_light_list[u_light_range.x ..+ u_light_range.y], ascending. A light left out adds exactly
// zero here, so looping over the list gives the same sum as looping over all lights.
uniform isamplerBuffer u_light_list;
uniform ivec2 u_light_range;
int listed_light(int j) { return texelFetch(u_light_list, u_light_range.x + j).r; }
// Per light, LIGHT_TEXELS RGBA32F texels (viewer/light_table.h): (radiance, outline start),
// (triangle start, triangle count, first shadow cube, shadow cube count), (centroid,
// bounding radius), (unit normal of a flat one-sided light or 0, luminance of radiance times
// area), (1 for a two-sided light, else 0; 0; 0; 0).
uniform samplerBuffer u_light_data;
const int LIGHT_TEXELS = 5;
// Quad lights also as their outline: 4 RGB32F texels from 4 * start; start -1 for others.
uniform samplerBuffer u_light_outlines;

// theta * dot(n, gamma) for the edge a -> b seen from the origin (a, b not normalised).
float edge_term(vec3 a, vec3 b, vec3 n) {
  vec3 c = cross(a, b);
  float len = length(c);
  if (len < 1e-12) return 0.0;
  // asin for small angles keeps the precision of small or distant lights (acos loses it near
  // 1), acos for the rest; both are much cheaper than atan2 on llvmpipe.
  float inv = inversesqrt(dot(a, a) * dot(b, b));
  float cos_theta = dot(a, b) * inv;
  float theta = cos_theta > 0.7 ? asin(min(len * inv, 1.0)) : acos(max(cos_theta, -1.0));
  return theta * dot(n, c) / len;
}

// Where the segment a -> b crosses the horizon (ha, hb: heights of a, b above it).
vec3 horizon_point(vec3 a, vec3 b, float ha, float hb) { return mix(a, b, ha / (ha - hb)); }

// Edge sum of triangle (v0, v1, v2) clipped to dot(n, v) >= 0; vertices relative to the
// shading point. Written out per case: local arrays are slow on llvmpipe.
float clipped_triangle_term(vec3 v0, vec3 v1, vec3 v2, vec3 n) {
  float h0 = dot(n, v0), h1 = dot(n, v1), h2 = dot(n, v2);
  bool u0 = h0 >= 0.0, u1 = h1 >= 0.0, u2 = h2 >= 0.0;
  int above = int(u0) + int(u1) + int(u2);
  if (above == 3) return edge_term(v0, v1, n) + edge_term(v1, v2, n) + edge_term(v2, v0, n);
  if (above == 0) return 0.0;
  // Rotate (keeping the winding) so that `a` is the odd one out: below when two are above,
  // above when one is.
  bool odd_is_above = above == 1;
  vec3 a = v0, b = v1, c = v2;
  float ha = h0, hb = h1, hc = h2;
  if (u1 == odd_is_above) { a = v1; b = v2; c = v0; ha = h1; hb = h2; hc = h0; }
  else if (u2 == odd_is_above) { a = v2; b = v0; c = v1; ha = h2; hb = h0; hc = h1; }
  vec3 ab = horizon_point(a, b, ha, hb);
  vec3 ca = horizon_point(c, a, hc, ha);
  if (odd_is_above) {
    // Triangle a, ab, ca.
    return edge_term(a, ab, n) + edge_term(ab, ca, n) + edge_term(ca, a, n);
  }
  // Quad ab, b, c, ca.
  return edge_term(ab, b, n) + edge_term(b, c, n) + edge_term(c, ca, n) + edge_term(ca, ab, n);
}

// E / pi from light `index` at p with shading normal n, unoccluded; a one-sided emitter lights
// only what is in front of it, a two-sided one both sides (each triangle's term is abs()ed).
// One exit, and the triangle loop runs zero times where the quad's outline gave the answer:
// llvmpipe shades 8 or 16 fragments in lock step and skips a loop only when no lane needs it.
vec3 light_irradiance_over_pi(int index, vec3 p, vec3 n) {
  vec4 head = texelFetch(u_light_data, LIGHT_TEXELS * index);
  vec2 triangles = texelFetch(u_light_data, LIGHT_TEXELS * index + 1).xy;
  int outline = int(head.a);
  int count = int(triangles.y);
  bool two_sided = texelFetch(u_light_data, LIGHT_TEXELS * index + 4).x > 0.0;
  float sum = 0.0;
  if (outline >= 0) {
    // A quad wholly above the horizon and in front: its 4 outer edges (the shared diagonal
    // of its two triangles cancels).
    vec3 a = texelFetch(u_light_outlines, 4 * outline).xyz - p;
    vec3 b = texelFetch(u_light_outlines, 4 * outline + 1).xyz - p;
    vec3 c = texelFetch(u_light_outlines, 4 * outline + 2).xyz - p;
    vec3 d = texelFetch(u_light_outlines, 4 * outline + 3).xyz - p;
    if (!two_sided && dot(cross(b - a, c - a), -a) <= 0.0) {
      count = 0;  // behind the emitter
    } else if (min(min(dot(n, a), dot(n, b)), min(dot(n, c), dot(n, d))) >= 0.0) {
      sum = abs(edge_term(a, b, n) + edge_term(b, c, n) + edge_term(c, d, n) + edge_term(d, a, n));
      count = 0;
    }
  }
  int start = int(triangles.x);
  for (int t = 0; t < count; ++t) {
    int base = 3 * (start + t);
    vec3 a = texelFetch(u_light_triangles, base).xyz - p;
    vec3 b = texelFetch(u_light_triangles, base + 1).xyz - p;
    vec3 c = texelFetch(u_light_triangles, base + 2).xyz - p;
    // One-sided: the point must be in front of the emitting face (CCW seen from the front).
    vec3 face = cross(b - a, c - a);
    if (!two_sided && dot(face, -a) <= 0.0) continue;
    // Seen from a point in front, the CCW triangle winds clockwise about -face, which makes
    // the edge sum negative; the abs() below takes care of the sign per triangle.
    sum += abs(clipped_triangle_term(a, b, c, n));
  }
  return head.rgb * (sum / TWO_PI);
}

#endif
