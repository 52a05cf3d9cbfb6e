#include "bake/lightmap/soft_texels.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <stdexcept>
#include <string>

#include "bake/accel.h"
#include "bake/hq/direct_light.h"
#include "bake/hq/final_gather.h"
#include "bake/lightmap/chart_filter.h"
#include "bake/lightmap/interleaved_strata.h"
#include "bake/lightmap/lightmap.h"
#include "bake/lightmap/texel_footprint.h"
#include "bake/lightmap/texel_receiver.h"

namespace lb {

namespace {

// The vertex radiosity at a footprint point, linear over the refined triangle; 0 where the
// point's surface is not the mesh's radiosity mesh.
vec3 interpolated_radiosity(const BakeResult& bake, const std::vector<const Mesh*>& surfaces,
                            const FootprintSample& p) {
  if (p.mesh >= bake.radiosity.meshes.size()) return vec3(0.0f);
  const MeshRadiosity& r = bake.radiosity.meshes[p.mesh];
  if (surfaces[p.mesh] != &r.mesh || r.vertex_radiance.size() != r.mesh.positions.size())
    return vec3(0.0f);
  const uvec3 tri = r.mesh.triangles[p.triangle];
  const float b1 = p.barycentric.x, b2 = p.barycentric.y, b0 = 1.0f - b1 - b2;
  return b0 * r.vertex_radiance[tri.x] + b1 * r.vertex_radiance[tri.y] +
         b2 * r.vertex_radiance[tri.z];
}

// The mean over `rays` cosine-distributed directions of 1 / (distance to the first surface),
// 0 for a miss: the reciprocal of the point's harmonic mean distance to its surroundings. A
// hit nearer than `nearest` counts as one at `nearest`.
float inverse_distance(const Accel& accel, const ReceiverPoint& x, uint64_t stream, int rays,
                       float nearest) {
  Rng rng(stream);
  int m = 1;
  while ((m + 1) * (m + 1) <= rays) ++m;
  const Frame frame(x.geometric_normal);
  double sum = 0.0;
  for (int k = 0; k < rays; ++k) {
    const vec2 jitter = rng.next_2d();
    const vec2 u = k < m * m ? stratified(k % m, k / m, m, m, jitter) : jitter;
    Ray ray;
    ray.direction = frame.to_world(square_to_cosine_hemisphere(glm::min(u, vec2(0.99999994f))));
    ray.origin = offset_ray_origin(x.position, x.geometric_normal, ray.direction);
    if (const auto hit = accel.intersect(ray)) sum += 1.0 / double(std::max(hit->t, nearest));
  }
  return float(sum / double(rays));
}

// Each node's box half-width in texels (soft_texels.h): filter_reach x its harmonic mean
// distance in its mesh's texels, at least 1 and at most filter_radius. `weight`: the nodes'
// areas (fill_texels), which say what a chart is. Counts the rays it casts into `rays`.
std::vector<int> filter_radii(const TexelFootprints& footprints,
                              const std::vector<const Mesh*>& surfaces, const Accel& accel,
                              const IlluminationMaps& maps, const std::vector<double>& weight,
                              const SoftTexelParams& params, FillTexelsParams fill,
                              const Progress& progress, std::atomic<uint64_t>& rays) {
  const int width = footprints.width(), height = footprints.height();
  std::vector<int> radius(footprints.cell_count(), params.filter_radius);
  if (!(params.filter_reach > 0.0f) || params.filter_radius == 0) return radius;
  fill.stage = "soft light: distances";
  fill.seed = hash_seed(params.seed, 0x9e0c);
  // Per node: x = the mean inverse distance, 1/m; y = the texel edge of its mesh, m.
  std::vector<vec3> proximity = fill_texels(
      footprints,
      [&](std::span<const FootprintSample> samples, std::span<vec3> values, size_t cell) {
        for (size_t s = 0; s < samples.size(); ++s) {
          const FootprintSample& p = samples[s];
          const float edge =
              p.mesh < maps.mesh_texel_size.size() && maps.mesh_texel_size[p.mesh] > 0.0f
                  ? maps.mesh_texel_size[p.mesh]
                  : maps.texel_size;
          const ReceiverPoint x = receiver_at_sample(*surfaces[p.mesh], p);
          values[s] = vec3(inverse_distance(accel, x, hash_seed(fill.seed, cell, s),
                                            kProximityRays, kNearestTexels * edge),
                           edge, 0.0f);
        }
        rays += uint64_t(samples.size()) * kProximityRays;
      },
      fill, progress);
  proximity = chart_box_filter(width, height, proximity, weight, kProximitySmoothing);
  for (size_t k = 0; k < radius.size(); ++k) {
    const float reach_texels = params.filter_reach / (proximity[k].x * proximity[k].y);
    if (reach_texels < float(params.filter_radius))  // false for inf and NaN (no hit, no node)
      radius[k] = std::max(1, int(reach_texels));
  }
  return radius;
}

}  // namespace

void check_soft_texel_params(const SoftTexelParams& p) {
  auto out_of_range = [](const char* name, int value, int lo, int hi) {
    if (value < lo || value > hi)
      throw std::invalid_argument(std::string("soft texels: ") + name + " = " +
                                  std::to_string(value) + " is outside [" + std::to_string(lo) +
                                  ", " + std::to_string(hi) + "]");
  };
  out_of_range("gather_rays", p.gather_rays, 0, 4096);
  out_of_range("points_side", p.points_side, 0, 8);
  out_of_range("filter_radius", p.filter_radius, 0, 16);
  if (!(p.filter_reach >= 0.0f && p.filter_reach <= 100.0f))
    throw std::invalid_argument("soft texels: filter_reach = " + std::to_string(p.filter_reach) +
                                " is outside [0, 100]");
  out_of_range("strata_levels", p.strata_levels, 0, kMaxStrataLevels);
  out_of_range("dilation_rings", p.dilation_rings, 0, 64);
}

SoftTexelMap soft_light_texels(const Scene& scene, const BakeResult& bake,
                               const SoftTexelParams& params, const Progress& progress) {
  check_soft_texel_params(params);
  const auto start = std::chrono::steady_clock::now();
  const IlluminationMaps& maps = bake.illumination;
  SoftTexelMap out;
  const int width = maps.width, height = maps.height;
  const size_t texels = size_t(width) * size_t(height);
  if (texels == 0) return out;

  std::vector<Mesh> storage;
  const std::vector<const Mesh*> surfaces = lightmap_surfaces(scene, bake, storage);
  const TexelFootprints footprints(surfaces, width, height);
  SoftTexelParams used = params;  // the automatic choices made
  used.points_side = params.points_side > 0
                         ? params.points_side
                         : side_for_budget(kSoftPointsBudget, footprints.touched_cells(), 1, 8);
  if (params.filter_radius > 0)
    used.filter_radius = std::max(1, params.filter_radius / used.points_side);

  // The base: the vertex radiosity resampled exactly (lightmap.h).
  FillTexelsParams fill;
  fill.rule = FootprintRule::quadrature;
  fill.stage = "soft light: resampling";
  std::vector<double> weight;
  const TexelEstimator interpolate = [&](std::span<const FootprintSample> samples,
                                         std::span<vec3> values, size_t) {
    for (size_t s = 0; s < samples.size(); ++s)
      values[s] = interpolated_radiosity(bake, surfaces, samples[s]);
  };
  out.radiance = fill_texels(footprints, interpolate, fill, progress, &weight);

  if (params.gather_rays > 0) {
    // The correction: the gather's footprint mean minus the interpolation's at the very same
    // points (same rule and seed), so it is the difference of two estimates of one mean however
    // a border cuts the footprint. Two fills, because fill_texels keeps values >= 0.
    // The gather reads the solution itself at its hits, not a map the bake may already hold.
    BakedScene baked = make_baked_scene(scene, bake);
    baked.soft_texels = nullptr;
    const Accel accel(baked.scene);
    const DirectLight direct(baked.scene, accel);
    const GatherContext context{baked, accel, direct};
    std::atomic<uint64_t> gather_rays{0}, shadow_rays{0};
    fill.rule = FootprintRule::stratified;
    fill.side = used.points_side;
    fill.seed = hash_seed(params.seed, 0x50f7);
    fill.stage = "soft light: final gather";
    fill.plane_fit_at_borders = false;  // noisy: see FillTexelsParams
    const uint64_t scramble = hash_seed(params.seed, 0x57a7);
    const std::vector<vec3> gathered = fill_texels(
        footprints,
        [&](std::span<const FootprintSample> samples, std::span<vec3> values, size_t cell) {
          GatherCounts counts;
          const SampleCell stratum =
              interleaved_stratum(int(cell % size_t(width)), int(cell / size_t(width)),
                                  used.strata_levels, scramble);
          for (size_t s = 0; s < samples.size(); ++s) {
            const ReceiverPoint x = receiver_at_sample(*surfaces[samples[s].mesh], samples[s]);
            values[s] = gather_soft_light(context, x, hash_seed(fill.seed, cell, s),
                                          params.gather_rays, stratum, &counts);
          }
          gather_rays += counts.rays;
          shadow_rays += counts.shadow;
        },
        fill, progress);
    fill.stage = "soft light: interpolation at the gather's points";
    const std::vector<vec3> interpolated = fill_texels(footprints, interpolate, fill, progress);
    std::vector<vec3> correction(texels);
    for (size_t k = 0; k < texels; ++k) correction[k] = gathered[k] - interpolated[k];
    std::atomic<uint64_t> distance_rays{0};
    const std::vector<vec3> smooth = chart_box_filter(
        width, height, correction, weight,
        filter_radii(footprints, surfaces, accel, maps, weight, used, fill, progress,
                     distance_rays));
    // Soft light is never negative; the clamp only acts where the noise exceeds the value.
    for (size_t k = 0; k < texels; ++k)
      if (weight[k] > 0.0) out.radiance[k] = glm::max(out.radiance[k] + smooth[k], vec3(0.0f));
    out.gather_rays = gather_rays;
    out.shadow_rays = shadow_rays;
    out.distance_rays = distance_rays;
  }

  std::vector<uint8_t> filled(texels, 0);
  for (size_t k = 0; k < texels; ++k) filled[k] = weight[k] > 0.0 ? 1 : 0;
  dilate_texels(width, height, filled, out.radiance, params.dilation_rings);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace lb
