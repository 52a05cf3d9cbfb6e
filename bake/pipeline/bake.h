#pragma once
// The whole bake: pass 1 (illumination maps) then pass 2 (vertex radiosity) on the scene
// with the atlas's lightmap UVs applied, so radiosity meshes carry them too, then the
// soft-light texel map from the solution (bake/lightmap/soft_texels.h) and, with the
// `directional` setting, its L1 band (bake/lightmap/soft_band.h).

#include <functional>
#include <optional>
#include <string>

#include "bake/illumination/illumination.h"
#include "bake/lightmap/soft_band.h"
#include "bake/lightmap/soft_texels.h"
#include "bake/quality.h"
#include "bake/radiosity/radiosity.h"

namespace lb {

struct BakeParams {
  IlluminationParams illumination;
  RadiosityParams radiosity;
  SoftTexelParams soft_texels;          // the soft-light texel map made after pass 2
  // With illumination.directional: the soft map's L1 band (bake/lightmap/soft_band.h), the
  // export's own gather's defaults (not in the settings table).
  DirectionalParams soft_band;
  uint64_t seed = 1;                    // overrides every stage's seed
  Quality quality = Quality::standard;  // the level apply_quality set (recorded in manifests)
};

// The quality levels (bake/quality.h) scale the work of both passes together from the
// standard level, which is the passes' own defaults:
//
//   level      patches   radiosity rays   caustic rays         soft-light gather rays
//   draft      x 1/4     x 1/4            x 1/4                0 (plain resampling)
//   standard   x 1       x 1 (4 M)        x 1 (512^2 a zone)   x 1 (8 a texel point)
//   high       x 2       x 4              x 2                  x 2
//   final      x 4       x 16             x 4                  x 4
//
// Patches: the automatic patch size (patches.h) over sqrt(factor), so each patch gets ray
// budget / patches rays times the ray factor over the patch factor: noise falls with the level
// as the patch bias does. Sets `quality`, radiosity.patch_size, radiosity.ray_budget,
// illumination.rays_per_zone_side and soft_texels.gather_rays; every other setting is left
// as it is.
void apply_quality(const Scene& scene, Quality quality, BakeParams& params);

// The level to bake at: the one asked for, else the scene file's, else standard.
Quality choose_quality(const Scene& scene, std::optional<Quality> asked);

// Optional hooks into a running bake (the viewer's live refinement); not settings, so apart
// from BakeParams and without effect on the result's bits.
struct BakeCallbacks {
  // Called on the baking thread with the result so far: once when pass 1 is done
  // (illumination maps complete, radiosity empty), then while pass 2 refines (radiosity
  // partial, see RadiosityCallbacks). The final result is returned, not passed here.
  std::function<void(const BakeResult&)> on_partial;
  double min_interval_seconds = 0.25;  // between radiosity partials
  // Called once the atlas is planned (its size sets every map's), before any dense ray: a
  // check that throws here (the output's free space) stops the bake before its work.
  std::function<void(int atlas_width, int atlas_height)> on_atlas;
};

// Builds the accelerator, runs both passes (progress stages "illumination..." then
// "radiosity...") and makes the soft-light texel map from their results ("soft light..."),
// and returns all three. Throws Cancelled when cancelled.
BakeResult bake_scene(const Scene& scene, const BakeParams& params, const Progress& progress = {},
                      const BakeCallbacks& callbacks = {});

// Pass 1 split across processes (issue 16; lightbake bake --shard, lightbake merge): each shard
// plans the whole pass (feelers, atlas; the same in every process) and traces its share of the
// dense rays into fixed-point sums; the shards' sums add, in any order, into the sums of the
// whole pass, bit for bit.
struct Pass1Shard {
  illumination::Pass1Sums sums;
  int atlas_width = 0, atlas_height = 0;
};
// Shard `shard` of `shard_count` of pass 1 (IlluminationPass::trace). Throws Cancelled.
Pass1Shard bake_pass1_shard(const Scene& scene, const BakeParams& params, int shard,
                            int shard_count, const Progress& progress = {});
// The whole bake from the summed sums of every shard: pass 1 finished (filter, radiance,
// dilation), then pass 2 and the soft-light map, as bake_scene would: the same bits. Throws
// std::invalid_argument when the sums' atlas is not this scene's and settings'.
BakeResult bake_from_pass1_sums(const Scene& scene, const BakeParams& params,
                                const illumination::Pass1Sums& sums, const Progress& progress = {});

// The scene the radiosity pass runs on: each mesh as the atlas laid it out (vertices split
// where charts meet, lightmap UVs set) where it has a map, so refined radiosity meshes
// interpolate the UVs too. The geometry and triangle order are the scene's.
Scene with_lightmap_uvs(const Scene& scene, const IlluminationMaps& maps);

}  // namespace lb
