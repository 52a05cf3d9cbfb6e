#pragma once
// The two baked terms at a hit, in the E/pi convention of bake/bake_result.h (multiply by the
// reflectance to get outgoing radiance): the illumination map (caustics) and the vertex
// radiosity (soft indirect light).

#include "bake/bake_result.h"
#include "bake/surface.h"

namespace lb {

// Bilinear lookup in the atlas at `lightmap_uv`. Texel (i, j) is centred on
// ((i + 0.5) / width, (j + 0.5) / height) and stored at radiance[j * width + i], the layout a
// GL texture upload of the same array samples with GL_LINEAR, so the viewer and the HQ renderer
// read the same values. Texels outside every chart (valid == 0) are left out of the bilinear
// weights, so the black gutter never bleeds in; coordinates are clamped to the atlas. (Every
// node whose tent touches a chart is valid and dilation fills the ring around, so inside a
// chart this equals the GPU's plain bilinear read: tested against the viewer per pixel in
// ViewerTerms.OneLitNodeIsReadAtTheSameUvByRasterAndHq.)
vec3 illumination_map_at(const IlluminationMaps& maps, vec2 lightmap_uv);

// Barycentric interpolation of the per-vertex radiosity of the hit's mesh (0 if it has none).
vec3 vertex_radiosity_at(const BakedScene& baked, const SurfacePoint& sp);

// The soft (radiosity) term at a hit as every renderer draws it: the bake's soft-light texel
// map (bake/lightmap/soft_texels.h), read as illumination_map_at reads the caustic atlas,
// where the bake has one and the hit's mesh has radiosity and lightmap UVs; else
// vertex_radiosity_at. With BakedScene::directional and the map's band (soft_l1), on a bump- or
// normal-mapped surface: the band decoded at the bumped normal with s = 0 (decode_directional,
// n0 = sp.shading_normal), from the same bilinear taps.
vec3 soft_light_at(const BakedScene& baked, const SurfacePoint& sp);

// The map term at a hit: 0 when the bake has no atlas or the mesh no lightmap UVs. With
// BakedScene::directional, the map's L1 band decoded (decode_directional, bake/sh_projection.h)
// at the bump- or normal-mapped normal (bumped_normal), n0 = sp.shading_normal: the bilinear
// L0, L1 and s of the texels, as a GPU's filtered reads give the viewer's shader.
vec3 illumination_at(const BakedScene& baked, const SurfacePoint& sp);

// Every light group's map and vertex radiosity terms at a hit (bake/light_groups.h), read as
// illumination_at and vertex_radiosity_at read the whole light's, times `weight`, added to
// `out` (one entry per of the `groups`). The groups' maps: per atlas texel, where its groups'
// values start in `map_values` (kNoGroupTexel: all 0, the caustic maps' usual texel;
// kOffChartGroupTexel: outside every chart, IlluminationMaps::valid 0), which
// holds each lit texel's groups side by side; `vertex_radiance`: per scene mesh, each vertex's
// groups side by side. So a hit reads all groups in one go (`map_start` empty: no map term).
// Returns the groups' map terms summed (the whole map's term, to rounding), unweighted.
inline constexpr uint32_t kNoGroupTexel = 0xffffffffu;
inline constexpr uint32_t kOffChartGroupTexel = 0xfffffffeu;  // valid == 0: left out
vec3 add_group_terms(const BakedScene& baked, const SurfacePoint& sp, size_t groups,
                     const std::vector<uint32_t>& map_start, const std::vector<vec3>& map_values,
                     const std::vector<std::vector<vec3>>& vertex_radiance, vec3 weight,
                     vec3* out);

}  // namespace lb
