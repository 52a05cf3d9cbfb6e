#pragma once
// The direct light a receiver would get if nothing stood in the way, in closed form (E/pi,
// W/(sr m^2), as bake_result.h): the numerator of the direct term's ratio estimator
// (lightmap.h; Heitz, Hill and McGuire, "Combining analytic direct illumination and stochastic
// shadows", 2018).
//
// Area lights: Lambert's formula for a polygon of uniform radiance L seen from x with normal n,
//     E = L/2 sum_edges theta_k (n . g_k),
// theta_k the angle the edge (a_k, a_k+1) subtends at x and g_k the unit normal of the plane
// through x and the edge, over each emitting triangle clipped to the half-spaces in front of
// the receiver's geometric and shading normals (where the Monte Carlo estimator's integrand
// lives: cos > 0 at both), and only from the side it emits to. Lamps: their exact value (one
// direction, no sampling). The sky is soft light (pass 2), not direct: it gives 0 here as in
// the direct term.

#include "bake/transport/direct_light.h"
#include "bake/light_sources.h"

namespace lb {

// Cost: a few dozen flops per emitting triangle, so the lightmap uses it only for scenes whose
// lights have at most kMaxAnalyticTriangles triangles in all.
inline constexpr size_t kMaxAnalyticTriangles = 256;
size_t emitting_triangle_count(const LightSources& sources);

vec3 unshadowed_direct(const Scene& scene, const LightSources& sources, const ReceiverPoint& x);

}  // namespace lb
