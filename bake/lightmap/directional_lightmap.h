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
//   soft     the bake's soft band where it has one (the `directional` setting: SoftTexelMap::l1),
//            else gather_soft_l1 (soft_band.h) here, the very gather the bake makes: the same
//            rays and filter at the same seed, so the two differ only where the bake's band
//            was de-ringed against the soft map alone and in the gutters;
//   caustic  the bake's caustic band where it has one (pass 1's arrival directions), else
//            none (light through mirrors and glass drawn as if from the normal's direction).
// Nodes with no visible surface take their neighbours' L1 (dilation, as their L0), and L1 is
// de-ringed against the final L0 (after seams and gutters). The direct term's share of L0
// (sh_projection.h: the part of the decode that follows the cosine law) is the texel's direct
// term over its L0, in luminance, dilated likewise.
//
// Memory: 3 more RGB maps the atlas's size (4x the plain map); cost: the direct term's rays
// are shared, the soft gather adds gather_rays rays (and their shadow rays) per footprint point
// (none when the bake has the soft band).

#include <array>
#include <vector>

#include "bake/lightmap/lightmap.h"
#include "bake/lightmap/soft_band.h"
#include "bake/sh_projection.h"

namespace lb {

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

// The direct term (contents all) with its L1, per node, before the other terms join: what
// `lightbake export --directional --shard i/n` bakes for its rows and merge joins.
struct DirectBand {
  int width = 0;
  int height = 0;
  std::vector<vec3> l0;                 // width*height: bake_lightmap's direct term, bit for bit
  std::array<std::vector<vec3>, 3> l1;  // per world axis, not yet dilated nor de-ringed
  std::vector<uint8_t> filled;          // 1 where points of visible surface were estimated
  TexelRows rows;                       // the node rows held (all of them unsharded), 0 elsewhere
  // The direct term's ratio denominator at the same points (the unshadowed light: Lightmap::
  // direct_unshadowed), width*height; empty from shards that do not carry it.
  std::vector<vec3> unshadowed;
  uint64_t shadow_rays = 0;
  uint64_t points = 0;
  double seconds = 0.0;
};

// The direct band of params.shard's node rows of params.shard_count (the rows bake_lightmap's
// shards take, partition_texel_rows), or of every row; each node has the bits of the unsharded
// one's. Throws std::invalid_argument without `contents all`; Cancelled when cancelled.
DirectBand bake_direct_band(const Scene& scene, const BakeResult& bake,
                            const LightmapParams& params, const Progress& progress = {});

// `direct` (contents all): the direct band already baked, every row (shards joined); null:
// baked here. Throws std::invalid_argument for a sharded direct term (params.shard_count > 1),
// a band not of the atlas or a parameter out of range; Cancelled when `progress` is cancelled.
Lightmap bake_directional_lightmap(const Scene& scene, const BakeResult& bake,
                                   const LightmapParams& params,
                                   const DirectionalParams& directional, DirectionalMaps& out,
                                   const Progress& progress = {},
                                   const DirectBand* direct = nullptr);

// The band of texel k.
inline ShL1 texel_band(const Lightmap& map, const DirectionalMaps& band, size_t k) {
  return {map.radiance[k], {band.l1[0][k], band.l1[1][k], band.l1[2][k]}, band.share[k]};
}

}  // namespace lb
