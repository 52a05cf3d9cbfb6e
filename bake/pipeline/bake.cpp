#include "bake/pipeline/bake.h"

#include "bake/accel.h"

namespace lb {

Scene with_lightmap_uvs(const Scene& scene, const IlluminationMaps& maps) {
  Scene out = scene;
  for (size_t m = 0; m < out.meshes.size() && m < maps.lightmap_uvs.size(); ++m)
    if (maps.lightmap_uvs[m].size() == out.meshes[m].positions.size())
      out.meshes[m].lightmap_uvs = maps.lightmap_uvs[m];
  return out;
}

BakeResult bake_scene(const Scene& scene, const BakeParams& params, const Progress& progress) {
  BakeResult result;
  result.seed = params.seed;
  const Accel accel(scene);

  IlluminationParams illumination = params.illumination;
  illumination.seed = params.seed;
  result.illumination = trace_illumination(scene, accel, illumination, progress);
  progress.throw_if_cancelled();

  // Same geometry, so the accelerator over `scene` serves the copy too.
  const Scene uv_scene = with_lightmap_uvs(scene, result.illumination);
  RadiosityParams radiosity = params.radiosity;
  radiosity.seed = params.seed;
  result.radiosity = solve_radiosity(uv_scene, accel, radiosity, progress);
  return result;
}

}  // namespace lb
