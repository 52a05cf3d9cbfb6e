#pragma once
// The soft-light texel map (issue 11): the radiosity term per lightmap texel node, in the
// convention of bake_result.h (E/pi, W/(sr m^2), before the reflectance), computed at bake
// time and saved with the bake, so that the raster viewer, the snapshot and the export all draw
// the same texels instead of interpolating vertex radiosity.
//
// How: the plain resampling of the vertex radiosity (quadrature, lightmap.h) is the base; a
// final gather (bake/transport/final_gather.h: one diffuse bounce from the solution, whose first
// indirect bounce carries none of the patches' bias) estimates each node's correction
//     correction(node) = gathered(node) - resampled(node)
// over the node's footprint (fill_texels, stratified: `points_side`^2 points a cell, 4 cells a
// node, `gather_rays` rays a point). The correction is noisy and mostly smooth, so it is
// averaged over the nodes of the same chart within a box (weighted by texel area) before it is
// added: the map keeps the resampling's smoothness and takes the gather's mean. gather_rays = 0
// gives the plain resampling.
//
// The box's size follows the light's, as irradiance caching's does (Ward et al. 1988): the
// correction changes fast where other surfaces are near (contacts, corners) and slowly in the
// open, over about the node's harmonic mean distance R to the surfaces around it (the radius of
// validity of an irradiance value, from the split-sphere bound). So a node's box half-width is
// `filter_reach` x R, at most `filter_radius` texels and at least one (R: below; misses count
// as infinitely far), and two nodes average each other only within both their radii
// (chart_filter.h).
//
// Cost: cells x points_side^2 x (gather_rays + kProximityRays) rays, more where boxes narrow
// (box_rays_max), each gather ray with one shadow ray (measured numbers and the choice of the
// defaults: bench/results/LOG.md).
// Deterministic: every point's rays come from its own stream (seed, cell, point), the filter
// is a fixed-order sum, so the bits do not depend on the thread count.

#include <cstdint>
#include <vector>

#include "bake/bake_result.h"
#include "bake/lightmap/chart_filter.h"
#include "bake/progress.h"

namespace lb {

inline constexpr double kSoftPointsBudget = 262144.0;  // points_side 0: points over the atlas
// Game densities: gather rays over the atlas's points (20 a point at the points budget).
inline constexpr double kSoftGatherBudget = 20.0 * kSoftPointsBudget;
inline constexpr int kSoftMaxGatherRays = 64;

struct SoftTexelParams {
  // Gather rays per footprint point; 0 = no gather (the plain resampling). Range 0..4096.
  // Noise of the correction falls as 1/sqrt(rays x points in the filter), cost grows linearly.
  // 8 (more where boxes narrow: box_rays_max): the proximity boxes follow the darkening at
  // contacts and the rays pay for their noise (bench/results/LOG.md).
  // At game densities (automatic points_side of 2 or more: under 65,536 cells, and texels
  // coarser than 1.5 x scene diagonal / 256, the automatic rule's) each point takes more: as
  // many as `game_gather_budget` over the atlas's points allows (at least 20 with
  // kSoftGatherBudget), up to kSoftMaxGatherRays, never fewer than this (soft_texel_choices).
  int gather_rays = 8;
  // Footprint points per cell side (1..8): side^2 points a cell; 0 = automatic: as many as
  // kSoftPointsBudget points over the atlas's cells allow, 1 to 8 (side_for_budget). Atlases of
  // over 65,536 cells (the bundled scenes at their automatic density) take 1; the Cornell box
  // at 20 texels/m takes 5 and at 10 texels/m 8: a texel 10 cm wide then samples its surface
  // about as finely as one of 1-2 cm, which the soft light's changes near contacts and corners
  // need (its error there fell from 3.7% to 2.6% of the light, issue 36; docs/export.md).
  int points_side = 0;
  // Largest half-width in texels of the box the correction is averaged over, within one chart
  // (0..16), divided by points_side (at least 1): a node with side^2 times the points needs a
  // box side^2 times smaller for the same noise, and a wide box smears what the extra points
  // resolve. Wider = less noise where the light is smooth; filter_reach narrows it elsewhere.
  // At game densities (above) the box spans the node's neighbours only (half-width 1): its
  // texels are 5-20 cm wide, a wider box blurs the contacts and corners, and the extra rays
  // pay for its noise (the Cornell box at 20 texels/m, the soft light's error in 4 x 4 pixel
  // blocks: 1.75% -> 1.29% of the light, 1.48% with the rays alone; docs/export.md).
  int filter_radius = 10;
  // A node's box half-width at most this times its harmonic mean distance to the surfaces
  // around it (0..100; 0 = every box filter_radius wide, no proximity rays). 0.25 with the
  // rays following the box (box_rays_max) since 8 Dec 2026 (0.7 before): the soft light
  // darkens into a crease or a block's foot over a few texels and a wider box averaged that
  // away (the Cornell box's texels within 2 cm of a contact +3.5% too bright on average
  // against Cycles, bench/cycles_bake_race.py; docs/export.md).
  float filter_reach = 0.25f;
  // What a node takes from its box (chart_filter.h): the mean moved to the node (default since
  // 7 Dec 2026), or the plain mean. Beside a crease the box is cut by the chart's border and its
  // narrower neighbours, and the plain mean, a point inside the chart's, missed the darkening
  // into the crease: the Cornell box's texels at creases were 3.5-5% too bright against Cycles
  // (bench/cycles_bake_race.py; the moved mean: 2.3-2.4%, every covered texel's error lower).
  // At game densities the plain mean (soft_texel_choices: a 3 x 3 box's slope is too noisy).
  ChartFit filter_fit = ChartFit::mean_at_node;
  // Levels of interleaved strata (interleaved_strata.h, 0..4): cells take turns over 4^L
  // sub-squares of the hemisphere. One level: a node's four cells cover its four quadrants.
  // 0 (the whole hemisphere at every cell) since 8 Dec 2026: the quadrants balance only in
  // whole boxes, and a box clipped by its chart's border or narrowed near a contact holds
  // some quadrants twice and others not at all, an error that depends on the seed and that
  // no number of rays removes (at the Cornell box's contacts the seed-to-seed noise was 7.5%
  // with one level and 3.1% without, at 10 texels/m 2.1% and 1.2%; bench/results/LOG.md).
  int strata_levels = 0;
  // Gather rays over the atlas's points at game densities (gather_rays above); 0 = none beyond
  // gather_rays and the box of filter_radius / points_side (the rule before 7 Dec 2026).
  double game_gather_budget = kSoftGatherBudget;
  // Gather rays whose hit lies nearer than this (metres; 0 = none) gather that hit's own soft
  // light with `regather_rays` rays instead of reading its vertex radiosity (final_gather.h);
  // the bake sets it to the radiosity's patch edge. 0..4096 rays.
  float regather_distance = 0.0f;
  int regather_rays = 2;
  // Rays follow the box: a cell whose nodes' boxes are narrower than filter_radius gathers
  // (2 filter_radius + 1)^2 / (2 r + 1)^2 times gather_rays (r the narrowest of its nodes'
  // half-widths), at most this many times (1..64; 1 = the same rays everywhere), so that a
  // narrow box near a contact averages about as many rays as a wide one in the open: the
  // correction's noise falls as 1 / sqrt(rays x nodes in the box).
  int box_rays_max = 4;
  uint64_t seed = 1;       // overridden by the bake's seed
  int dilation_rings = 3;  // >= the atlas padding, so bilinear reads never see black
};

// How a node's harmonic mean distance is estimated (filter_reach > 0): kProximityRays rays a
// footprint point, a hit nearer than kNearestTexels texels counted as one that far, and the
// mean inverse distance averaged over the nodes within kProximitySmoothing texels (5 x 5 nodes,
// whose footprints hold 6 x 6 cells: ~70 rays). 1/d has a heavy tail at contacts: without the
// floor and the smoothing, two seeds gave the room's nodes different radii and its map 1.8x the
// seed-to-seed noise of the fixed 6-texel box, with them 0.8x (test_soft_texels.cpp).
inline constexpr int kProximityRays = 2;
inline constexpr float kNearestTexels = 3.0f;
inline constexpr int kProximitySmoothing = 2;

// The choices soft_light_texels makes for an atlas of `touched_cells` cells: points_side,
// gather_rays and filter_radius as used (points_side 0 resolved by kSoftPointsBudget; at game
// densities, 2 or more points a side chosen so, the rays from kSoftGatherBudget and a box of
// half-width 1 with its plain mean, header).
SoftTexelParams soft_texel_choices(const SoftTexelParams& params, size_t touched_cells);

// Throws std::invalid_argument naming the field when a value is out of range.
void check_soft_texel_params(const SoftTexelParams& params);

// The map for `bake` (its illumination atlas and radiosity solution) of `scene` (the scene the
// bake was made from). Empty when the bake has no atlas. Throws Cancelled when cancelled.
SoftTexelMap soft_light_texels(const Scene& scene, const BakeResult& bake,
                               const SoftTexelParams& params, const Progress& progress = {});

}  // namespace lb
