#pragma once
// The soft-light texel map (issue 11): the radiosity term per lightmap texel node, in the
// convention of bake_result.h (E/pi, W/(sr m^2), before the reflectance), computed at bake
// time and saved with the bake, so that the raster viewer, the snapshot and the export all draw
// the same texels instead of interpolating vertex radiosity.
//
// How: the plain resampling of the vertex radiosity (quadrature, lightmap.h) is the base; a
// final gather (bake/hq/final_gather.h: one diffuse bounce from the solution, whose first
// indirect bounce carries none of the patches' bias) estimates each node's correction
//     correction(node) = gathered(node) - resampled(node)
// over the node's footprint (fill_texels, stratified: `points_side`^2 points a cell, 4 cells a
// node, `gather_rays` rays a point). The correction is noisy and mostly smooth, so it is
// averaged over the nodes of the same chart within `filter_radius` texels (weighted by texel
// area) before it is added: the map keeps the resampling's smoothness and takes the gather's
// mean. gather_rays = 0 gives the plain resampling.
//
// Cost: cells x points_side^2 x gather_rays gather rays, each with one shadow ray (measured
// numbers and the choice of the defaults: docs/speed-accuracy.md). Deterministic: every
// point's rays come from its own stream (seed, cell, point), the filter is a fixed-order sum,
// so the bits do not depend on the thread count.

#include <cstdint>
#include <vector>

#include "bake/bake_result.h"
#include "bake/progress.h"

namespace lb {

struct SoftTexelParams {
  // Gather rays per footprint point; 0 = no gather (the plain resampling). Range 0..4096.
  // Noise of the correction falls as 1/sqrt(rays x points in the filter), cost grows linearly.
  int gather_rays = 4;
  // Footprint points per cell side (1..8): side^2 points a cell.
  int points_side = 1;
  // Half-width in texels of the box the correction is averaged over, within one chart (0..16).
  // Wider = less noise, but a correction that changes fast (contacts) is smeared.
  int filter_radius = 6;
  // Levels of interleaved strata (interleaved_strata.h, 0..4): cells take turns over 4^L
  // sub-squares of the hemisphere. One level: a node's four cells cover its four quadrants.
  // More levels stratify a filter box further but leave each node fewer sub-squares: measured
  // worse (docs/speed-accuracy.md).
  int strata_levels = 1;
  uint64_t seed = 1;       // overridden by the bake's seed
  int dilation_rings = 3;  // >= the atlas padding, so bilinear reads never see black
};

// Throws std::invalid_argument naming the field when a value is out of range.
void check_soft_texel_params(const SoftTexelParams& params);

// The map for `bake` (its illumination atlas and radiosity solution) of `scene` (the scene the
// bake was made from). Empty when the bake has no atlas. Throws Cancelled when cancelled.
SoftTexelMap soft_light_texels(const Scene& scene, const BakeResult& bake,
                               const SoftTexelParams& params, const Progress& progress = {});

}  // namespace lb
