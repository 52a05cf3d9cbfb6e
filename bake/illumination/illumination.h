#pragma once
// Pass 1: illumination ray tracing (Shirley 1990, section 3.1; Arvo 1986). Feeler rays find
// the specular objects seen from each light, dense stratified rays follow light through
// mirrors, glass and glossy metal and splat its power onto the illumination maps of the
// diffuse surfaces they reach. Light that reaches a diffuse surface first is not recorded.
//
// Zones: the unit square is cut into feeler_zones^2 zones and mapped to the light's
// cosine-weighted hemisphere through the concentric disk (Figure 2, right). That map is a
// continuous bijection from the square onto the disk, so two zones touch on the hemisphere
// exactly when they touch in the square: the 8-neighbourhood in the square grid is the
// whole adjacency, with no wrap-around (the square's border is the horizon, one closed loop).
// Each zone (and sub-zone, see subzones_side) carries its area's fraction of the light's
// power because the map preserves the cosine-weighted measure. Details and measured numbers:
// docs/illumination.md.
//
// Lamps and the sky (issue 14) get zones in the square their own rays are drawn from
// (light_rays.h): a point lamp's sphere, a spot's outer cone, the disk of a directional lamp's
// parallel rays, and per sky direction (sky_directions_side^2 of them) the same disk.
//
// Small specular objects: besides the grid feelers, aimed feelers are sent at each specular
// mesh's bounding sphere (a stratified aimed_feelers_side^2 grid over the sphere's disk as
// seen from the ray origin), so an object smaller than one zone is still found if any of its
// aimed feelers hits it: always for objects that fill their bounding disk from the centre
// (balls, plates seen face on); thin objects (a wire ring) need aimed_feelers_side larger
// than the disk-radius / wire-width ratio.

#include <cstdint>
#include <memory>
#include <vector>

#include "bake/accel.h"
#include "bake/bake_result.h"
#include "bake/illumination/fixed_sums.h"
#include "bake/progress.h"

namespace lb {

struct IlluminationParams {
  int feeler_zones = 6;           // feelers on a feeler_zones^2 grid over the hemisphere
  int feelers_per_zone_side = 2;  // feelers per zone: this^2 (1..4; 2 costs 144 rays a light)
  int aimed_feelers_side = 4;     // aimed feelers per specular mesh and light: this^2
  int rays_per_zone_side = 512;   // dense rays per traced zone: rays_per_zone_side^2
  // Each zone is cut into subzones_side^2 sub-zones with a feeler each (in zones found by the
  // grid or aimed feelers, and their neighbours); only sub-zones that saw a specular surface,
  // and their neighbours, get dense rays, at the same density: (rays_per_zone_side /
  // subzones_side)^2 each (rounded up). 1 = the paper's single level.
  int subzones_side = 8;
  // Density filter of the map after the splat (density_filter.h): each node's power spreads,
  // energy kept, over a disk of nodes that holds at least `filter_deposits` deposits (summed
  // bilinear weights), at most `filter_max_radius` texels; dense caustics keep radius 0 and
  // stay sharp, sparse halos are smoothed. More deposits: smoother and blurrier sparse light
  // (noise ~ 1/sqrt(deposits)). Measured numbers: docs/illumination.md.
  bool density_filter = true;
  float filter_deposits = 256.0f;  // 1..1e6
  int filter_max_radius = 8;       // texels, 1..64
  // The sky's caustics: sky_directions_side^2 stratified directions drawn by the sky's
  // radiance, each traced as parallel rays like a directional lamp with 1/sky_directions_side
  // of the dense rays per sub-zone side (so the sky costs about one lamp). Unbiased; fewer
  // directions leave separate images of the caustic, more blur it into the sky's (1..64).
  int sky_directions_side = 8;
  // Caustic pilot (issue 11): before the atlas, the traced sub-zones get 1/pilot_divisor^2 of
  // their dense rays, and each diffuse mesh's deposits are counted on a coarse grid (cells of 4
  // base texels; base = texel_size, or the automatic size). A mesh whose densest cell would put
  // more than filter_deposits deposits in a base texel at the full ray count gets texels of
  // sqrt(filter_deposits / density), rounded up to base / 2^(k/2), at least base / 4: finer
  // texels would hold fewer than filter_deposits, which the density filter spreads back over
  // a disk (and 256 deposits are ~6% noise a texel). A mesh's own texel_size wins.
  bool pilot_texels = true;
  int pilot_divisor = 8;  // 1..64
  // The density filter leaves alone the meshes whose texels the pilot refined: their peak
  // texels hold >= filter_deposits deposits already, and in their fringe the filter's wide
  // kernels only carry light across the caustic's sharp edge into the dark around it.
  // cornell_glass's floor pixels of the caustic's neighbourhood (docs/illumination.md): HQ 16
  // spp MRE 0.064 -> 0.031, raster 0.055 -> 0.028 against a converged window reference, at no
  // cost. Meshes the pilot left at the base size (sparse caustics: fig3, fig4, fig7) are
  // filtered as before.
  bool pilot_skips_filter = true;
  int max_depth = 16;             // specular bounces before a path is dropped
  int roulette_depth = 3;         // bounces before Russian roulette starts
  float texel_size = 0.0f;        // map texel edge, metres; 0 = automatic (see atlas.h)
  int atlas_max_size = 2048;      // largest atlas edge, texels
  int atlas_padding = 3;          // texels between charts, >= 2
  float chart_angle_deg = 40.0f;  // chart growth: max angle to the seed face's normal
  // Unwrap meshes that bring their own lightmap UVs too (AtlasParams::generate_lightmap_uvs).
  bool generate_lightmap_uvs = false;
  // Diagnostics and references: trace every zone (no feelers), and independent random
  // directions within each sub-zone instead of its jittered grid.
  bool trace_all_zones = false;
  bool stratified = true;
  // Directional maps (issue 38): beside each node's power, the L1 band of the arriving light
  // (sh_projection.h; each deposit's arrival direction, the same splat, filter and dilation as
  // the power), so IlluminationMaps::l1 is filled. The map itself keeps its bits either way.
  bool directional = false;
  // Benchmarks only: if set, receives every ray the dense pass cast (feelers excluded), so
  // raw Embree can be timed on exactly the same rays.
  std::vector<Ray>* cast_log = nullptr;
  uint64_t seed = 1;
};

// Limits on the parameters, so an absurd value is an error rather than a run of days. Memory no
// longer grows with the rays (each deposit is splatted as it arrives, fixed_sums.h), only time:
// 16384^2 a zone is 1024x the default's rays, ~9 CPU minutes for the room's pass 1 (0.5 s at
// the default) and days for a level with a hundred lights; shard it (IlluminationPass).
constexpr int kMaxRaysPerZoneSide = 16384;
constexpr int kMaxFeelerGridSide = 1024;  // feeler_zones * subzones_side

// Throws std::invalid_argument naming the parameter if `params` is outside the limits above
// (or a count is not positive).
void check_illumination_params(const IlluminationParams& params);

// Pass 1 in three steps, so that its dense rays can be split across processes (issue 16):
//  1. the constructor checks the parameters, sets up the lights, sends the feelers, plans the
//     blocks of dense rays (light x sub-zone x rows, batched by ~4096 rays) and builds the
//     atlas: all from the scene and the parameters, the same in every process;
//  2. trace() traces the batches of one shard and splats every deposit straight into the
//     fixed-point sums (fixed_sums.h): no deposit is kept, and the sums of the shards added in
//     any order have the bits of one whole trace, whatever the thread counts;
//  3. finish() turns the whole pass's sums into the maps: density filter, radiance, dilation.
// trace_illumination is the three in one process.
class IlluminationPass {
 public:
  // Throws std::invalid_argument on bad parameters (check_illumination_params).
  IlluminationPass(const Scene& scene, const Accel& accel, const IlluminationParams& params,
                   const Progress& progress = {});
  ~IlluminationPass();
  IlluminationPass(const IlluminationPass&) = delete;
  IlluminationPass& operator=(const IlluminationPass&) = delete;

  illumination::Pass1Sums empty_sums() const;  // zeros, one per atlas node
  // Adds the dense rays of shard `shard` of `shard_count` (pass1_batch_shards) into `sums`.
  // Throws Cancelled when cancelled (the sums are then partial), illumination::FixedOverflow.
  void trace(illumination::Pass1Sums& sums, int shard = 0, int shard_count = 1,
             const Progress& progress = {}) const;
  // The maps from the sums of every shard. Stats: the feelers' from this process, the rays'
  // from the sums; seconds from this object's construction.
  IlluminationMaps finish(const illumination::Pass1Sums& sums, const Progress& progress = {}) const;

  int atlas_width() const;
  int atlas_height() const;
  size_t batch_count() const;
  uint64_t planned_rays() const;  // dense rays of every batch

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The shard each batch of dense rays belongs to, given the batches' ray counts, in batch order:
// each batch goes to the shard with the fewest rays so far (lowest index on a tie). Depends on
// the plan alone, never on threads.
std::vector<int> pass1_batch_shards(const std::vector<uint64_t>& batch_rays, int shard_count);

// Throws std::invalid_argument on bad parameters (check_illumination_params).
IlluminationMaps trace_illumination(const Scene& scene, const Accel& accel,
                                    const IlluminationParams& params,
                                    const Progress& progress = {});

// Dense rays the feelers saved: rays tracing every zone would have cost, minus the rays sent
// and the feelers.
int64_t rays_saved_by_feelers(const IlluminationStats& stats, const IlluminationParams& params);

// Inverse of square_to_disk (Shirley-Chiu): unit disk -> [0,1]^2. Used to find the zone of
// an aimed feeler's direction.
vec2 disk_to_square(vec2 d);

}  // namespace lb
