#pragma once
// Bump mapping (Blinn 1978) for the direct-light cosine: the shading normal perturbed by a
// height map or replaced by a tangent-space normal map.

#include "bake/surface.h"

namespace lb {

// The shading normal at `sp` after the material's bump map; unit, on the same side of the
// surface as sp.shading_normal. Without a bump map it is sp.shading_normal.
//  - height: p' = p + h(uv) * bump_scale * n, n' = normalize(dp'/du x dp'/dv), the height's
//    derivatives by central differences one texel apart.
//  - normal_map: glTF convention, n' = normalize(T x + B y + N z) with (x, y, z) = 2 c - 1,
//    x and y scaled by bump_scale, B = w * (N x T); T from the mesh's tangents, else from the
//    triangle's UV derivatives.
vec3 bumped_normal(const Scene& scene, const SurfacePoint& sp);

// The one normal every ray tracer (pass 1, pass 2, HQ mode, the reference) reflects and
// refracts about at a specular hit, so a bump-mapped mirror bakes the caustic it renders: the
// bump-mapped shading normal, or the geometric one where the two disagree about the side the
// ray comes from (a tessellated ball's silhouette, a bump tipped past the surface).
vec3 specular_normal(const Scene& scene, const SurfacePoint& sp, vec3 incident);

}  // namespace lb
