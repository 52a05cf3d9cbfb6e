#pragma once
// The whole bake: pass 1 (illumination maps) then pass 2 (vertex radiosity) on the scene
// with the atlas's lightmap UVs applied, so radiosity meshes carry them too, then the
// soft-light texel map from the solution (bake/lightmap/soft_texels.h).

#include <functional>
#include <string>

#include "bake/illumination/illumination.h"
#include "bake/lightmap/soft_texels.h"
#include "bake/radiosity/radiosity.h"

namespace lb {

struct BakeParams {
  IlluminationParams illumination;
  RadiosityParams radiosity;
  SoftTexelParams soft_texels;  // the soft-light texel map made after pass 2
  uint64_t seed = 1;            // overrides every stage's seed
};

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
// "radiosity...") and makes the soft-light texel map from their results ("soft light..."),
// and returns all three. Throws Cancelled when cancelled.
BakeResult bake_scene(const Scene& scene, const BakeParams& params, const Progress& progress = {},
                      const BakeCallbacks& callbacks = {});

// The scene the radiosity pass runs on: each mesh as the atlas laid it out (vertices split
// where charts meet, lightmap UVs set) where it has a map, so refined radiosity meshes
// interpolate the UVs too. The geometry and triangle order are the scene's.
Scene with_lightmap_uvs(const Scene& scene, const IlluminationMaps& maps);

}  // namespace lb
