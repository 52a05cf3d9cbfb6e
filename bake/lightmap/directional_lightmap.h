#pragma once
// The export's lightmap with its L1 band (issue 38; the convention: sh_projection.h).
//
// L0 is bake_lightmap's map bit for bit: the direct term's texels (contents all) are filled
// here by the very estimator, points and order bake_lightmap uses, each point's shadow ray also
// giving its direction, and handed to bake_lightmap as the direct term already baked; the L1 of
// the direct term comes from the same rays at no extra ray cost.
//
// Per term:
//   direct   (contents all) the one-shadow-ray samples above: L1 += P (value / cos) w;
//   soft     a gather of the bake's solution (bake/transport/final_gather.h: gathered_radiance, the
//            soft term's own estimator) at `gather_rays` uniform hemisphere directions per
//            footprint point (uniform, not cosine: the L1 weight tan(theta) would give the
//            cosine-weighted estimate infinite variance), then averaged over `filter_radius`
//            texels within the chart (chart_filter.h), as the soft map's correction is;
//   caustic  no L1 (light through mirrors and glass is drawn as if it came from the normal's
//            own direction): pass 1 keeps no arrival directions.
// Nodes with no visible surface take their neighbours' L1 (dilation, as their L0), and L1 is
// de-ringed against the final L0 (after seams and gutters). The direct term's share of L0
// (sh_projection.h: the part of the decode that follows the cosine law) is the texel's direct
// term over its L0, in luminance, dilated likewise.
//
// Memory: 3 more RGB maps the atlas's size (4x the plain map); cost: the direct term's rays
// are shared, the soft gather adds gather_rays rays (and their shadow rays) per footprint point.

#include <array>
#include <vector>

#include "bake/lightmap/lightmap.h"
#include "bake/sh_projection.h"

namespace lb {

struct DirectionalParams {
  int gather_rays = 4;     // soft term: uniform hemisphere rays a footprint point (0..4096)
  int points_side = 1;     // soft term: footprint points a cell side (1..8)
  int filter_radius = 3;   // soft term: box half-width in texels within a chart (0..16)
};

struct DirectionalMaps {
  int width = 0;
  int height = 0;
  // Per world axis x, y, z: width*height RGB coefficients, W/(sr m^2) per unit of n, de-ringed.
  std::array<std::vector<vec3>, 3> l1;
  // Per texel, the direct term's share of L0 (luminance), in [0, 1]: 0 without `contents all`.
  std::vector<float> share;
  uint64_t gather_rays = 0;
  double seconds = 0.0;  // the L1 band's own work (the soft gather, combining, de-ringing)
};

// Throws std::invalid_argument for a sharded direct term (params.shard_count > 1) or a
// parameter out of range; Cancelled when `progress` is cancelled.
Lightmap bake_directional_lightmap(const Scene& scene, const BakeResult& bake,
                                   const LightmapParams& params,
                                   const DirectionalParams& directional, DirectionalMaps& out,
                                   const Progress& progress = {});

// The band of texel k.
inline ShL1 texel_band(const Lightmap& map, const DirectionalMaps& band, size_t k) {
  return {map.radiance[k], {band.l1[0][k], band.l1[1][k], band.l1[2][k]}, band.share[k]};
}

}  // namespace lb
