#pragma once
// A Blinn height map as the tangent-space normal map (glTF convention) that shades the same
// (issue 38): glTF has no height bump, so without this an exported bump-mapped wall drew flat
// in every engine and in `snapshot out.glb`, and its directional lightmap had no normal to
// answer. The viewer's height bump (shaders/bump.glsl, bake/bump.h) tilts the normal by the
// surface gradient of h = bump_scale x texture: n' = normalize(n - k (h_u grad_u + h_v grad_v)),
// the derivatives by central differences one texel apart. On a mesh whose UVs run s_u metres
// per unit of u and s_v per unit of v (orthogonal), in the tangent frame T = dP/du,
// B = w (N x T) = b dP/dv / |dP/dv| (b = +-1: the mesh's TANGENT handedness; b = -1, glTF's
// "+y is image up", where a mesh has no tangents), that is the normal map
//     n_ts = normalize(-k h_u / s_u, -b k h_v / s_v, 1).
// s_u and s_v come from the meshes that use the material (area-weighted means of |dP/du| and
// |dP/dv|): one normal map per material, exact where every such mesh has the same UV scale
// (TOML boxes and quads with uv_tile).

#include "bake/scene.h"

namespace lb {

// How the meshes using `material` carry UVs: metres per unit of u and v (area-weighted means;
// (0, 0) if none) and b, the side of dP/dv their bitangents lie on (the area's majority).
struct UvFrame {
  vec2 metres{0.0f};
  float bitangent_along_v = -1.0f;
};
UvFrame uv_frame(const Scene& scene, int material);

// The normal map of `height` (first channel) for `bump_scale` metres per unit of it, on UVs
// laid as `frame` says; RGB, linear (not colour), texel = 0.5 n + 0.5.
Texture height_to_normal_map(const Texture& height, float bump_scale, const UvFrame& frame);

}  // namespace lb
