#pragma once
// The whole bake: pass 1 (illumination maps) then pass 2 (vertex radiosity) on the scene
// with the atlas's lightmap UVs applied, so radiosity meshes carry them too.

#include <string>

#include "bake/illumination/illumination.h"
#include "bake/radiosity/radiosity.h"

namespace lb {

struct BakeParams {
  IlluminationParams illumination;
  RadiosityParams radiosity;
  uint64_t seed = 1;  // overrides both passes' seeds
};

// Builds the accelerator, runs both passes (progress stages "illumination..." then
// "radiosity..."), and returns both results. Throws Cancelled when cancelled.
BakeResult bake_scene(const Scene& scene, const BakeParams& params, const Progress& progress = {});

// The scene the radiosity pass runs on: `scene` with each mesh's lightmap UVs taken from the
// atlas where it has them (so refined radiosity meshes interpolate them too).
Scene with_lightmap_uvs(const Scene& scene, const IlluminationMaps& maps);

}  // namespace lb
