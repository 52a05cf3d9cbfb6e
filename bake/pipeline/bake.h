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

BakeResult bake_scene(const Scene& scene, const BakeParams& params, const Progress& progress = {});

}  // namespace lb
