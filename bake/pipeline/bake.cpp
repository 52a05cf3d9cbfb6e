#include "bake/pipeline/bake.h"

#include <cmath>
#include <string>
#include <utility>

#include "bake/accel.h"
#include "bake/illumination/atlas.h"
#include "bake/light_groups.h"
#include "bake/radiosity/patches.h"
#include "bake/work_limits.h"

namespace lb {

Scene with_lightmap_uvs(const Scene& scene, const IlluminationMaps& maps) {
  Scene out = scene;
  for (size_t m = 0; m < out.meshes.size(); ++m)
    out.meshes[m] = mesh_with_lightmap(scene.meshes[m], maps, m);
  return out;
}

namespace {

struct QualityFactors {
  double patches;  // patch count, x the standard level's
  double radiosity_rays;
  double caustic_rays;
  int soft_gather_rays;  // x the standard level's; 0 = the plain resampling
};

QualityFactors factors(Quality quality) {
  switch (quality) {
    case Quality::draft:
      return {0.25, 0.25, 0.25, 0};
    case Quality::standard:
      return {1.0, 1.0, 1.0, 1};
    case Quality::high:
      return {2.0, 4.0, 2.0, 2};
    case Quality::final:
      return {4.0, 16.0, 4.0, 4};
  }
  return {1.0, 1.0, 1.0, 1};
}

}  // namespace

void apply_quality(const Scene& scene, Quality quality, BakeParams& params) {
  params.quality = quality;
  const QualityFactors f = factors(quality);
  const BakeParams standard;
  params.radiosity.patch_size =
      quality == Quality::standard
          ? standard.radiosity.patch_size  // automatic, as the pass itself chooses
          : float(double(automatic_patch_size(scene)) / std::sqrt(f.patches));
  params.radiosity.ray_budget =
      uint64_t(std::llround(double(standard.radiosity.ray_budget) * f.radiosity_rays));
  params.illumination.rays_per_zone_side = int(
      std::lround(double(standard.illumination.rays_per_zone_side) * std::sqrt(f.caustic_rays)));
  params.soft_texels.gather_rays = standard.soft_texels.gather_rays * f.soft_gather_rays;
  // The sky's caustic directions with the caustic rays: draft 4 x 4, standard 8 x 8, high
  // 11 x 11, final 16 x 16 (few directions show a sky's caustic as separate sharp images).
  params.illumination.sky_directions_side = int(
      std::lround(double(standard.illumination.sky_directions_side) * std::sqrt(f.caustic_rays)));
  // Texel density with the caustic rays, so each texel catches as many photons at every level
  // (texels x 1/4, 2, 4: edge x 2, 1/sqrt(2), 1/2).
  std::vector<bool> diffuse(scene.meshes.size());
  for (size_t m = 0; m < scene.meshes.size(); ++m)
    diffuse[m] = scene.materials[size_t(scene.meshes[m].material)].is_diffuse();
  params.illumination.texel_size =
      quality == Quality::standard
          ? standard.illumination.texel_size  // automatic, as the pass itself chooses
          : float(double(automatic_texel_size(scene, diffuse, params.illumination.atlas_max_size)) /
                  std::sqrt(f.caustic_rays));
}

Quality choose_quality(const Scene& scene, std::optional<Quality> asked) {
  return asked ? *asked : scene.quality.value_or(Quality::standard);
}

namespace {

void check_bake_params(const Scene& scene, const BakeParams& params) {
  check_illumination_params(params.illumination);
  check_radiosity_params(scene, params.radiosity);
  check_soft_texel_params(params.soft_texels);
  if (params.illumination.directional) check_directional_params(params.soft_band);
  const size_t triangles = triangle_count(scene);
  require_memory("a bake of " + std::to_string(triangles) + " triangles, which",
                 estimate_bake_bytes(triangles));
}

IlluminationParams pass1_params(const BakeParams& params) {
  IlluminationParams illumination = params.illumination;
  illumination.seed = params.seed;
  return illumination;
}

// Pass 2 and the soft-light map after pass 1's maps.
BakeResult bake_after_pass1(const Scene& scene, const Accel& accel, const BakeParams& params,
                            IlluminationMaps illumination, const Progress& progress,
                            const BakeCallbacks& callbacks) {
  BakeResult result;
  result.seed = params.seed;
  result.light_groups = light_group_names(scene);
  result.illumination = std::move(illumination);
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
  // Short gather rays gather again within a patch edge of their start (final_gather.h).
  soft.regather_distance = radiosity.patch_size > 0.0f ? radiosity.patch_size
                                                       : automatic_patch_size(scene);
  result.soft_texels = soft_light_texels(scene, result, soft, progress);
  // Directional maps: the soft map's L1 band too (soft_band.h), its L0 unchanged.
  if (params.illumination.directional)
    soft_light_band(scene, result, result.soft_texels, params.soft_band, params.seed,
                    soft.dilation_rings, progress);
  // Its working maps, which malloc would keep while the maps are written (OpenImageIO's
  // libraries and buffers on top): bench/light_groups.py's room held 186 MiB resident here
  // with one group, 104 after this; with four groups 292, 193.
  release_freed_memory();
  return result;
}

}  // namespace

BakeResult bake_scene(const Scene& scene, const BakeParams& params, const Progress& progress,
                      const BakeCallbacks& callbacks) {
  // Both passes' settings are checked before any ray is traced.
  check_bake_params(scene, params);
  const Accel accel(scene);
  const IlluminationPass pass(scene, accel, pass1_params(params), progress);
  if (callbacks.on_atlas) callbacks.on_atlas(pass.atlas_width(), pass.atlas_height());
  illumination::Pass1Sums sums = pass.empty_sums();
  pass.trace(sums, 0, 1, progress);
  IlluminationMaps maps = pass.finish(sums, progress);
  // Freed before pass 2: the fixed-point sums (32 B a texel, up to 24 more per light group,
  // 72 more when directional).
  sums = illumination::Pass1Sums();
  if (!maps.group_radiance.empty()) release_freed_memory();
  return bake_after_pass1(scene, accel, params, std::move(maps), progress, callbacks);
}

Pass1Shard bake_pass1_shard(const Scene& scene, const BakeParams& params, int shard,
                            int shard_count, const Progress& progress) {
  check_bake_params(scene, params);  // a shard refuses what the whole bake would
  const Accel accel(scene);
  const IlluminationPass pass(scene, accel, pass1_params(params), progress);
  Pass1Shard out{pass.empty_sums(), pass.atlas_width(), pass.atlas_height()};
  pass.trace(out.sums, shard, shard_count, progress);
  return out;
}

BakeResult bake_from_pass1_sums(const Scene& scene, const BakeParams& params,
                                const illumination::Pass1Sums& sums, const Progress& progress) {
  check_bake_params(scene, params);
  const Accel accel(scene);
  const IlluminationPass pass(scene, accel, pass1_params(params), progress);
  if (sums.nodes() != size_t(pass.atlas_width()) * size_t(pass.atlas_height()))
    throw std::invalid_argument("pass 1 shards: their atlas is not this scene's and settings'");
  if (sums.groups() != light_group_names(scene).size())
    throw std::invalid_argument("pass 1 shards: their light groups are not this scene's");
  return bake_after_pass1(scene, accel, params, pass.finish(sums, progress), progress, {});
}

}  // namespace lb
