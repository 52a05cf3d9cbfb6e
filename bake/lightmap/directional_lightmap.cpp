#include "bake/lightmap/directional_lightmap.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <functional>
#include <mutex>
#include <numeric>
#include <span>
#include <stdexcept>
#include <string>

#include "bake/accel.h"
#include "bake/transport/direct_light.h"
#include "bake/transport/final_gather.h"
#include "bake/lightmap/soft_band.h"
#include "bake/lightmap/texel_footprint.h"
#include "bake/lightmap/texel_receiver.h"
#include "bake/sampling.h"

namespace lb {

namespace {

// Fills `channels` values per sample (values[s * channels + c]).
using ChannelEstimator =
    std::function<void(std::span<const FootprintSample> samples, std::span<vec3> values,
                       size_t cell)>;

// fill_texels (texel_footprint.h) for several values per point, tent-weighted means only (the
// noisy estimators here keep the mean at borders too). Channel 0 is summed and clamped exactly
// as fill_texels sums and clamps (same points, weights and order of additions), so it has
// fill_texels' bits; the other channels are signed and not clamped. params.rows: those node
// rows only (a shard's), the cell row above them computed again as fill_texels does.
std::vector<std::vector<vec3>> fill_texel_channels(const TexelFootprints& footprints,
                                                   int channels, const ChannelEstimator& estimate,
                                                   const FillTexelsParams& params,
                                                   const Progress& progress,
                                                   std::vector<double>* weight_out) {
  const int width = footprints.width(), height = footprints.height();
  const size_t nodes = size_t(width) * size_t(height);
  const size_t k_channels = size_t(channels);
  std::vector<std::vector<vec3>> values(k_channels, std::vector<vec3>(nodes, vec3(0.0f)));
  if (weight_out) weight_out->assign(nodes, 0.0);
  const int side = std::max(1, params.side);
  // Per cell, per corner: the weight, then channels x 3 weighted sums.
  const size_t stride = 1 + 3 * k_channels, cell_size = 4 * stride;
  const auto hidden = [&](const FootprintSample& p) {
    const std::vector<std::vector<uint8_t>>& flags = *params.hidden_triangles;
    return p.mesh < flags.size() && p.triangle < flags[p.mesh].size() &&
           flags[p.mesh][p.triangle] != 0;
  };
  auto fill_cell_row = [&](int j, double* row) {
    std::vector<FootprintSample> samples;
    std::vector<vec3> estimates;
    for (int i = 0; i < width; ++i) {
      const size_t cell = size_t(j) * size_t(width) + size_t(i);
      if (footprints.cell_empty(cell)) continue;
      samples.clear();
      footprints.cell_samples(i, j, params.rule, side, params.seed, samples);
      if (params.hidden_triangles) std::erase_if(samples, hidden);
      if (samples.empty()) continue;
      estimates.assign(samples.size() * k_channels, vec3(0.0f));
      estimate(samples, estimates, cell);
      double* out = row + size_t(i) * cell_size;
      for (size_t s = 0; s < samples.size(); ++s) {
        const double x = samples[s].in_cell.x, y = samples[s].in_cell.y;
        const double tent[4] = {(1 - x) * (1 - y), x * (1 - y), (1 - x) * y, x * y};
        for (size_t k = 0; k < 4; ++k) {
          double* corner = out + k * stride;
          const double weight = tent[k] * double(samples[s].area);
          corner[0] += weight;
          for (size_t c = 0; c < k_channels; ++c) {
            const glm::dvec3 add = weight * glm::dvec3(estimates[s * k_channels + c]);
            for (int e = 0; e < 3; ++e) corner[1 + 3 * c + size_t(e)] += add[e];
          }
        }
      }
    }
  };
  const TexelRows fill_rows = params.rows.value_or(TexelRows{0, height});
  if (fill_rows.begin < 0 || fill_rows.end > height || fill_rows.count() < 0)
    throw std::invalid_argument("fill_texel_channels: node rows outside the atlas");
  std::vector<double> previous(size_t(width) * cell_size), band;
  // Another shard fills the rows above: their last cell row again, the same bits.
  if (fill_rows.begin > 0) fill_cell_row(fill_rows.begin - 1, previous.data());
  std::atomic<int> rows_done{0};
  std::mutex report;
  for (int band_start = fill_rows.begin; band_start < fill_rows.end;
       band_start += kTexelBandRows) {
    const int rows = std::min(kTexelBandRows, fill_rows.end - band_start);
    band.assign(size_t(rows) * size_t(width) * cell_size, 0.0);
    std::atomic<bool> stopped{false};
    tbb::parallel_for(0, rows, [&](int r) {
      if (stopped || progress.cancelled()) {
        stopped = true;
        return;
      }
      fill_cell_row(band_start + r, &band[size_t(r) * size_t(width) * cell_size]);
      const int done = ++rows_done;
      std::lock_guard lock(report);
      progress.update(params.stage, double(done) / double(std::max(1, fill_rows.count())));
    });
    progress.throw_if_cancelled();
    tbb::parallel_for(0, rows, [&](int r) {
      const int j = band_start + r;
      std::vector<double> sum(stride);
      for (int i = 0; i < width; ++i) {
        std::fill(sum.begin(), sum.end(), 0.0);
        const int ci[4] = {i - 1, i, i - 1, i}, cj[4] = {j - 1, j - 1, j, j},
                  corner[4] = {3, 2, 1, 0};
        for (int k = 0; k < 4; ++k) {
          if (ci[k] < 0 || ci[k] >= width || cj[k] < 0) continue;
          const double* cell =
              cj[k] < band_start
                  ? &previous[size_t(ci[k]) * cell_size]
                  : &band[(size_t(cj[k] - band_start) * size_t(width) + size_t(ci[k])) *
                          cell_size];
          const double* c = cell + size_t(corner[k]) * stride;
          for (size_t e = 0; e < stride; ++e) sum[e] += c[e];
        }
        const size_t node = size_t(j) * size_t(width) + size_t(i);
        if (weight_out) (*weight_out)[node] = sum[0];
        if (!(sum[0] > 0.0)) continue;
        for (size_t c = 0; c < k_channels; ++c) {
          const glm::dvec3 mean =
              glm::dvec3(sum[1 + 3 * c], sum[2 + 3 * c], sum[3 + 3 * c]) / sum[0];
          values[c][node] = c == 0 ? vec3(glm::max(mean, glm::dvec3(0.0))) : vec3(mean);
        }
      }
    });
    std::copy_n(band.begin() + std::ptrdiff_t(size_t(rows - 1) * size_t(width) * cell_size),
                size_t(width) * cell_size, previous.begin());
  }
  return values;
}

// bake_lightmap's direct estimator (lightmap.cpp: the same direct_light_samples, so the same
// values), each value followed by its L1 (l1_of_sample along its shadow ray).
ChannelEstimator direct_band_estimator(const DirectLight& direct, const Accel& accel,
                                       const std::vector<const Mesh*>& surfaces, uint64_t seed,
                                       std::atomic<uint64_t>& shadow_rays,
                                       std::atomic<uint64_t>& points) {
  return [&direct, &accel, &surfaces, seed, &shadow_rays, &points](
             std::span<const FootprintSample> samples, std::span<vec3> values, size_t cell) {
    const size_t n = samples.size();
    points += n;
    std::vector<DirectLightSample> light_samples;
    direct_light_samples(seed, cell, n, light_samples);
    uint64_t rays = 0;
    for (size_t s = 0; s < n; ++s) {
      const ReceiverPoint x = receiver_at_sample(*surfaces[samples[s].mesh], samples[s]);
      Ray shadow_ray;
      const DeferredEstimate e = direct.sample_one_light(x, light_samples[s].u_select,
                                                         light_samples[s].u_light, shadow_ray);
      rays += e.shadow_ray ? 1 : 0;
      values[5 * s + 4] = e.value;  // unshadowed: the ratio estimator's denominator
      if (!e.shadow_ray || accel.occluded(shadow_ray)) continue;  // the rest stay 0
      values[5 * s] = e.value;
      const std::array<vec3, 3> band =
          l1_of_sample(e.value, glm::normalize(shadow_ray.direction), x.shading_normal);
      for (size_t a = 0; a < 3; ++a) values[5 * s + 1 + a] = band[a];
    }
    shadow_rays += rays;
  };
}

// What the direct band and the rest of the map are filled on, as bake_lightmap makes it: the
// lightmap's surfaces, their footprints on the atlas, the scene's rays and its hidden surface.
struct AtlasSurfaces {
  std::vector<Mesh> storage;
  std::vector<const Mesh*> surfaces;
  TexelFootprints footprints;
  Accel accel;
  std::vector<std::vector<uint8_t>> hidden;
  AtlasSurfaces(const Scene& scene, const BakeResult& bake, const LightmapParams& params)
      : surfaces(lightmap_surfaces(scene, bake, storage)),
        footprints(surfaces, bake.illumination.width, bake.illumination.height),
        accel(scene),
        hidden(params.skip_hidden_surface ? hidden_surface_triangles(surfaces, accel)
                                          : std::vector<std::vector<uint8_t>>{}) {}
};

// The direct band (DirectBand) of `params`' shard rows on the atlas's footprints.
DirectBand direct_band(const Scene& scene, const LightmapParams& params,
                       const TexelFootprints& footprints, const Accel& accel,
                       const std::vector<const Mesh*>& surfaces,
                       const std::vector<std::vector<uint8_t>>& hidden,
                       const Progress& progress) {
  const auto start = std::chrono::steady_clock::now();
  DirectBand out;
  out.width = footprints.width();
  out.height = footprints.height();
  const DirectLight direct(scene, accel);
  std::atomic<uint64_t> shadow_rays{0}, points{0};
  // bake_lightmap's fill parameters and shard rows.
  FillTexelsParams fill =
      noisy_fill(direct_side_for(params, footprints), hash_seed(params.seed, 0xd12ec7),
                 "lightmap: direct light and its direction", hidden);
  if (params.shard_count > 1)
    fill.rows = partition_texel_rows(texel_row_work(footprints, &hidden),
                                     params.shard_count)[size_t(params.shard)];
  out.rows = fill.rows.value_or(TexelRows{0, out.height});
  std::vector<double> weight;
  std::vector<std::vector<vec3>> channels = fill_texel_channels(
      footprints, 5,
      direct_band_estimator(direct, accel, surfaces, fill.seed, shadow_rays, points), fill,
      progress, &weight);
  out.l0 = std::move(channels[0]);
  for (size_t a = 0; a < 3; ++a) out.l1[a] = std::move(channels[a + 1]);
  out.unshadowed = std::move(channels[4]);
  out.filled.resize(weight.size());
  for (size_t k = 0; k < weight.size(); ++k) out.filled[k] = weight[k] > 0.0;
  out.shadow_rays = shadow_rays;
  out.points = points;
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace

DirectBand bake_direct_band(const Scene& scene, const BakeResult& bake,
                            const LightmapParams& params, const Progress& progress) {
  if (params.contents != LightmapContents::all)
    throw std::invalid_argument("directional lightmaps: a direct band needs contents all");
  if (params.shard_count < 1 || params.shard < 0 || params.shard >= params.shard_count)
    throw std::invalid_argument("lightmap: shard " + std::to_string(params.shard) + " of " +
                                std::to_string(params.shard_count));
  const AtlasSurfaces atlas(scene, bake, params);
  return direct_band(scene, params, atlas.footprints, atlas.accel, atlas.surfaces, atlas.hidden,
                     progress);
}

Lightmap bake_directional_lightmap(const Scene& scene, const BakeResult& bake,
                                   const LightmapParams& params,
                                   const DirectionalParams& directional, DirectionalMaps& out,
                                   const Progress& progress, const DirectBand* given) {
  if (params.shard_count != 1)
    throw std::invalid_argument("directional lightmaps: the direct term cannot be sharded");
  check_directional_params(directional);
  const IlluminationMaps& maps = bake.illumination;
  const int width = maps.width, height = maps.height;
  const size_t texels = size_t(width) * size_t(height);
  if (given && (params.contents != LightmapContents::all || given->width != width ||
                given->height != height || given->rows != TexelRows{0, height} ||
                given->l0.size() != texels || given->filled.size() != texels ||
                given->l1[0].size() != texels || given->l1[1].size() != texels ||
                given->l1[2].size() != texels ||
                (!given->unshadowed.empty() && given->unshadowed.size() != texels)))
    throw std::invalid_argument("directional lightmaps: the direct band given is not the "
                                "whole atlas's of contents all");
  out = DirectionalMaps{};
  out.width = width;
  out.height = height;
  for (auto& axis : out.l1) axis.assign(texels, vec3(0.0f));
  out.share.assign(texels, 0.0f);
  if (texels == 0) return bake_lightmap(scene, bake, params, progress);

  const AtlasSurfaces atlas(scene, bake, params);
  const std::vector<const Mesh*>& surfaces = atlas.surfaces;
  const TexelFootprints& footprints = atlas.footprints;
  const Accel& accel = atlas.accel;
  const std::vector<std::vector<uint8_t>>& hidden = atlas.hidden;
  std::vector<uint8_t> filled(texels, 0);

  // The direct term, L0 and L1 from one set of shadow rays (bake_lightmap's fill parameters).
  DirectBand baked;
  if (params.contents == LightmapContents::all && !given)
    baked = direct_band(scene, params, footprints, accel, surfaces, hidden, progress);
  const DirectBand& band = given ? *given : baked;
  const std::vector<vec3>* direct_l0 = nullptr;
  if (params.contents == LightmapContents::all) {
    direct_l0 = &band.l0;
    out.l1 = band.l1;
    filled = band.filled;
  }
  // Its ratio denominator came with it (older shards' bands lack it: sampled again).
  const std::vector<vec3>* unshadowed =
      direct_l0 && !band.unshadowed.empty() ? &band.unshadowed : nullptr;
  Lightmap lightmap = bake_lightmap(scene, bake, params, progress, direct_l0, unshadowed);
  lightmap.shadow_rays += band.shadow_rays;
  lightmap.direct_points += band.points;
  lightmap.seconds += band.seconds;

  const auto start = std::chrono::steady_clock::now();
  const SoftTexelMap& soft = bake.soft_texels;
  const bool soft_band = soft.radiance.size() == texels && soft.l1[0].size() == texels &&
                         soft.l1[1].size() == texels && soft.l1[2].size() == texels;
  if (soft_band && directional.gather_rays > 0) {
    // The bake's own band (the `directional` setting): the same gather, made at bake time
    // (gather_rays 0 still asks for no soft L1).
    const bool use_valid = maps.valid.size() == texels;
    for (size_t a = 0; a < 3; ++a)
      for (size_t k = 0; k < texels; ++k) out.l1[a][k] += soft.l1[a][k];
    for (size_t k = 0; k < texels; ++k)
      filled[k] = filled[k] || (use_valid ? maps.valid[k] != 0 : soft.radiance[k] != vec3(0.0f));
  } else if (directional.gather_rays > 0) {
    const SoftGather gather = gather_soft_l1(scene, bake, footprints, surfaces, hidden,
                                             directional, params.seed, progress);
    for (size_t a = 0; a < 3; ++a)
      for (size_t k = 0; k < texels; ++k) out.l1[a][k] += gather.l1[a][k];
    for (size_t k = 0; k < texels; ++k) filled[k] = filled[k] || gather.weight[k] > 0.0;
    out.gather_rays = gather.rays;
  }
  // The caustic term's L1 where the bake has it (the `directional` setting: pass 1's arrival
  // directions, bake/illumination/illumination.h), on the same atlas.
  const IlluminationMaps& caustic = bake.illumination;
  const bool caustic_band = caustic.width == width && caustic.height == height &&
                            caustic.l1[0].size() == texels && caustic.radiance.size() == texels &&
                            caustic.l1_share.size() == texels;
  if (caustic_band)
    for (size_t a = 0; a < 3; ++a)
      for (size_t k = 0; k < texels; ++k) out.l1[a][k] += caustic.l1[a][k];
  // Each node's mean shading normal (node_normals): the folds of charts unfolded across an edge
  // (a block's faces) mix L1 of two tangent planes; without the projection a flat face drew
  // L1 . n0 != 0 (the Cornell box's short block 2% off its plain map, measured).
  std::vector<vec3> normals = node_normals(footprints, surfaces, hidden, progress);
  // The share of L0 from small sources: the direct term's where it was taken, and the caustic
  // term's where it has a band (its share is 1: illumination.cpp).
  std::vector<vec3> share(texels, vec3(0.0f));
  const bool direct_share = lightmap.direct_term.size() == texels;
  if (direct_share || caustic_band)
    for (size_t k = 0; k < texels; ++k) {
      const float all = luminance(lightmap.radiance[k]);
      const vec3 small = (direct_share ? lightmap.direct_term[k] : vec3(0.0f)) +
                         (caustic_band ? caustic.radiance[k] * caustic.l1_share[k] : vec3(0.0f));
      // The caustic map's nodes count as filled here even without a gather or direct term.
      const bool known = filled[k] || (caustic_band && caustic.valid.size() == texels &&
                                       caustic.valid[k]);
      if (known && all > 0.0f) share[k] = vec3(std::clamp(luminance(small) / all, 0.0f, 1.0f));
    }
  // Nodes without visible surface and the gutters: their neighbours' L1, as L0 gets.
  dilate_texels(width, height, filled, normals, params.dilation_rings);
  dilate_texels(width, height, filled, share, params.dilation_rings);
  for (size_t k = 0; k < texels; ++k) out.share[k] = share[k].x;
  for (auto& axis : out.l1) dilate_texels(width, height, filled, axis, params.dilation_rings);
  project_to_tangent_planes(normals, out.l1);
  for (size_t k = 0; k < texels; ++k)
    dering(lightmap.radiance[k], out.l1[0][k], out.l1[1][k], out.l1[2][k]);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return lightmap;
}

}  // namespace lb
