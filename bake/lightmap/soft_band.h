#pragma once
// The soft term's L1 band (issue 38; the convention: bake/sh_projection.h): one gather that the
// export's directional map (directional_lightmap.h) and the bake's soft-light map (the
// `directional` setting, soft_light_band below) both use.
//
// The gather reads the bake's solution (bake/transport/final_gather.h: gathered_radiance, the
// soft term's own estimator) at `gather_rays` uniform hemisphere directions about the
// receiver's shading normal per footprint point (uniform, not cosine: the L1 weight tan(theta)
// would give the cosine-weighted estimate infinite variance), then averages them over
// `filter_radius` texels within the chart (chart_filter.h), as the soft map's correction is.
// Each point's rays come from its own stream (seed, cell, point) and the filter is a
// fixed-order sum, so the bits do not depend on the thread count.
//
// Soft light arrives from the whole hemisphere, so its share s (the decode's) is 0: W = 1/2,
// E(n)/pi = L0 (1 + n . n0) / 2 + L1 . n, exact for a uniform sky (tests: SoftBand.*).

#include <array>
#include <cstdint>
#include <vector>

#include "bake/bake_result.h"
#include "bake/progress.h"

namespace lb {

class TexelFootprints;

struct DirectionalParams {
  int gather_rays = 4;     // soft term: uniform hemisphere rays a footprint point (0..4096)
  int points_side = 1;     // soft term: footprint points a cell side (1..8)
  int filter_radius = 3;   // soft term: box half-width in texels within a chart (0..16)
};

// Throws std::invalid_argument when a field is out of range.
void check_directional_params(const DirectionalParams& params);

struct SoftGather {
  // Per world axis, per node: the chart-filtered L1 of the gather (not projected, dilated or
  // de-ringed); 0 where no visible surface lies under a node.
  std::array<std::vector<vec3>, 3> l1;
  std::vector<double> weight;  // per node, the footprint's weight (0: no visible surface)
  uint64_t rays = 0;           // gather rays (intersect calls)
};

// The gather above over `footprints` (the atlas of `bake`, on `surfaces`: lightmap_surfaces),
// points on triangles flagged in `hidden` dropped (hidden_surface_triangles; empty: none).
// Streams from hash_seed(seed, 0x5d1). Throws Cancelled when cancelled.
SoftGather gather_soft_l1(const Scene& scene, const BakeResult& bake,
                          const TexelFootprints& footprints,
                          const std::vector<const Mesh*>& surfaces,
                          const std::vector<std::vector<uint8_t>>& hidden,
                          const DirectionalParams& params, uint64_t seed,
                          const Progress& progress = {});

// Each node's mean shading normal over its footprint (not normalised; 0 where no visible
// surface): a chart unfolded across an edge has its box filter mix L1 of two tangent planes,
// and a node on the fold averages both, so L1 is projected to this normal's tangent plane.
std::vector<vec3> node_normals(const TexelFootprints& footprints,
                               const std::vector<const Mesh*>& surfaces,
                               const std::vector<std::vector<uint8_t>>& hidden,
                               const Progress& progress = {});

// Removes from each node's L1 its part along the node's normal (node_normals; nodes with a
// zero normal are left as they are).
void project_to_tangent_planes(const std::vector<vec3>& normals,
                               std::array<std::vector<vec3>, 3>& l1);

// The bake's soft band (`directional`): gather_soft_l1 on the bake's atlas over the bump- and
// normal-mapped surfaces only (the others draw the map whatever the band: n = n0 there; their
// nodes hold 0 or, in dilation's reach, a neighbour's L1), hidden surface dropped as the
// export's lightmap drops it, projected to the nodes' tangent planes, dilated
// `dilation_rings` times as the soft map is, and de-ringed against `map.radiance` (the soft
// map's L0, unchanged). Into map.l1 (left empty when no surface is bumped: no band),
// map.band_rays, map.band_seconds. `bake` must hold the atlas and the solution `map` was made
// from; `seed` is the bake's.
void soft_light_band(const Scene& scene, const BakeResult& bake, SoftTexelMap& map,
                     const DirectionalParams& params, uint64_t seed, int dilation_rings,
                     const Progress& progress = {});

}  // namespace lb
