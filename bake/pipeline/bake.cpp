#include "bake/pipeline/bake.h"

#include "bake/accel.h"

namespace lb {

Scene with_lightmap_uvs(const Scene& scene, const IlluminationMaps& maps) {
  Scene out = scene;
  for (size_t m = 0; m < out.meshes.size(); ++m)
    out.meshes[m] = mesh_with_lightmap(scene.meshes[m], maps, m);
  return out;
}

BakeResult bake_scene(const Scene& scene, const BakeParams& params, const Progress& progress,
                      const BakeCallbacks& callbacks) {
  // Both passes' settings are checked before any ray is traced.
  check_illumination_params(params.illumination);
  check_radiosity_params(scene, params.radiosity);
  check_soft_texel_params(params.soft_texels);
  BakeResult result;
  result.seed = params.seed;
  const Accel accel(scene);

  IlluminationParams illumination = params.illumination;
  illumination.seed = params.seed;
  result.illumination = trace_illumination(scene, accel, illumination, progress);
  progress.throw_if_cancelled();
  if (callbacks.on_partial) callbacks.on_partial(result);

  // Same geometry, so the accelerator over `scene` serves the copy too.
  const Scene uv_scene = with_lightmap_uvs(scene, result.illumination);
  RadiosityParams radiosity = params.radiosity;
  radiosity.seed = params.seed;
  RadiosityCallbacks radiosity_callbacks;
  if (callbacks.on_partial) {
    radiosity_callbacks.min_interval_seconds = callbacks.min_interval_seconds;
    // The partial radiosity rides in `result` (no copy of the maps); the final one replaces it.
    radiosity_callbacks.on_partial = [&](const VertexRadiosity& partial) {
      result.radiosity = partial;
      callbacks.on_partial(result);
    };
  }
  result.radiosity = solve_radiosity(uv_scene, accel, radiosity, progress, radiosity_callbacks);
  progress.throw_if_cancelled();
  SoftTexelParams soft = params.soft_texels;
  soft.seed = params.seed;
  result.soft_texels = soft_light_texels(scene, result, soft, progress);
  return result;
}

}  // namespace lb
