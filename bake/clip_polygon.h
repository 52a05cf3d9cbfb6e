#pragma once
// A triangle clipped to one texel cell: the atlas's exact node areas and the lightmap's texel
// footprints (bake/lightmap/texel_footprint.h) integrate over these pieces.

#include <cmath>

#include "bake/scene.h"

namespace lb {

// A convex polygon of at most 10 vertices: a triangle clipped by four axis-aligned lines
// gains at most one vertex per line.
struct ClipPolygon {
  vec2 p[10];
  int n = 0;
};

// Keeps the part of `in` where sign * (coordinate `axis` - bound) <= 0 (Sutherland-Hodgman).
inline ClipPolygon clip_polygon(const ClipPolygon& in, int axis, float bound, float sign) {
  ClipPolygon out;
  for (int k = 0; k < in.n; ++k) {
    const vec2 a = in.p[k], b = in.p[(k + 1) % in.n];
    const float da = sign * (a[axis] - bound), db = sign * (b[axis] - bound);
    if (da <= 0.0f) out.p[out.n++] = a;
    if ((da < 0.0f && db > 0.0f) || (da > 0.0f && db < 0.0f))
      out.p[out.n++] = a + (b - a) * (da / (da - db));
  }
  return out;
}

// The part of triangle (a, b, c) inside the unit square [0,1]^2.
inline ClipPolygon clip_to_unit_square(vec2 a, vec2 b, vec2 c) {
  ClipPolygon poly;
  poly.p[0] = a, poly.p[1] = b, poly.p[2] = c;
  poly.n = 3;
  poly = clip_polygon(poly, 0, 0.0f, -1.0f);
  poly = clip_polygon(poly, 0, 1.0f, 1.0f);
  poly = clip_polygon(poly, 1, 0.0f, -1.0f);
  return clip_polygon(poly, 1, 1.0f, 1.0f);
}

// Area of fan piece k (1 <= k < n - 1) of `poly`: the triangle p[0], p[k], p[k + 1], in the
// square's units. The pieces' areas sum to the polygon's.
inline double fan_piece_area(const ClipPolygon& poly, int k) {
  const vec2 a = poly.p[0], b = poly.p[k], c = poly.p[k + 1];
  return 0.5 * std::abs(double(b.x - a.x) * (c.y - a.y) - double(b.y - a.y) * (c.x - a.x));
}

}  // namespace lb
