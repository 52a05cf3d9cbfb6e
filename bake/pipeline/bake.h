#pragma once
// The whole bake: pass 1 (illumination maps) then pass 2 (vertex radiosity) on the scene
// with the atlas's lightmap UVs applied, so radiosity meshes carry them too.

#include <functional>
#include <optional>
#include <string>

#include "bake/illumination/illumination.h"
#include "bake/quality.h"
#include "bake/radiosity/radiosity.h"

namespace lb {

struct BakeParams {
  IlluminationParams illumination;
  RadiosityParams radiosity;
  uint64_t seed = 1;                    // overrides both passes' seeds
  Quality quality = Quality::standard;  // the level apply_quality set (recorded in manifests)
};

// The quality levels (bake/quality.h) scale the work of both passes together from the
// standard level, which is the passes' own defaults:
//
//   level      patches   radiosity rays   caustic rays
//   draft      x 1/4     x 1/4            x 1/4
//   standard   x 1       x 1 (4 M)        x 1 (512^2 a zone)
//   high       x 2       x 4              x 2
//   final      x 4       x 16             x 4
//
// Patches: the automatic patch size (patches.h) over sqrt(factor), so each patch gets ray
// budget / patches rays times the ray factor over the patch factor: noise falls with the level
// as the patch bias does. Sets `quality`, radiosity.patch_size, radiosity.ray_budget and
// illumination.rays_per_zone_side; every other setting is left as it is.
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
};

// Builds the accelerator, runs both passes (progress stages "illumination..." then
// "radiosity..."), and returns both results. Throws Cancelled when cancelled.
BakeResult bake_scene(const Scene& scene, const BakeParams& params, const Progress& progress = {},
                      const BakeCallbacks& callbacks = {});

// The scene the radiosity pass runs on: each mesh as the atlas laid it out (vertices split
// where charts meet, lightmap UVs set) where it has a map, so refined radiosity meshes
// interpolate the UVs too. The geometry and triangle order are the scene's.
Scene with_lightmap_uvs(const Scene& scene, const IlluminationMaps& maps);

}  // namespace lb
