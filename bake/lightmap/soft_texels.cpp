#include "bake/lightmap/soft_texels.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <stdexcept>
#include <string>

#include "bake/accel.h"
#include "bake/transport/direct_light.h"
#include "bake/transport/baked_terms.h"
#include "bake/transport/final_gather.h"
#include "bake/transport/gather_waves.h"
#include "bake/light_groups.h"
#include "bake/lightmap/chart_filter.h"
#include "bake/lightmap/interleaved_strata.h"
#include "bake/lightmap/lightmap.h"
#include "bake/lightmap/texel_footprint.h"
#include "bake/lightmap/texel_receiver.h"

namespace lb {

namespace {

// The vertex radiosity at a footprint point, linear over the refined triangle, into out[0]
// (no groups: the whole light's) or out[g * stride] (group g's of `groups`); 0 where the
// point's surface is not the mesh's radiosity mesh.
void interpolated_radiosity(const BakeResult& bake, const std::vector<const Mesh*>& surfaces,
                            const FootprintSample& p, size_t groups, vec3* out, size_t stride) {
  const size_t layers = std::max<size_t>(groups, 1);
  for (size_t l = 0; l < layers; ++l) out[l * stride] = vec3(0.0f);
  if (p.mesh >= bake.radiosity.meshes.size()) return;
  const MeshRadiosity& r = bake.radiosity.meshes[p.mesh];
  if (surfaces[p.mesh] != &r.mesh) return;
  const uvec3 tri = r.mesh.triangles[p.triangle];
  const float b1 = p.barycentric.x, b2 = p.barycentric.y, b0 = 1.0f - b1 - b2;
  for (size_t l = 0; l < layers; ++l) {
    const std::vector<vec3>& radiance =
        groups == 0 ? r.vertex_radiance : bake.radiosity.group_vertex_radiance[l][p.mesh];
    if (radiance.size() == r.mesh.positions.size())
      out[l * stride] = b0 * radiance[tri.x] + b1 * radiance[tri.y] + b2 * radiance[tri.z];
  }
}

// The light groups' terms for the gather (final_gather.h), from the bake's group arrays; the
// direct light's and the sky's groups from the scene's lights. Empty without groups.
GatherGroups gather_groups(const BakedScene& baked, const DirectLight& direct,
                           const BakeResult& bake) {
  GatherGroups out;
  const size_t groups = bake.light_groups.size();
  if (groups == 0) return out;
  out.groups = groups;
  // Texel- and vertex-major, as the gather's hits read them (one cache line for every group);
  // of the maps only the texels some caustic reached.
  const auto& group_maps = bake.illumination.group_radiance;
  const size_t texels = bake.illumination.radiance.size();
  if (!baked.illumination_black) {
    out.map_start.assign(texels, kNoGroupTexel);
    const std::vector<uint8_t>& valid = bake.illumination.valid;
    for (size_t k = 0; k < texels; ++k) {
      if (valid.size() == texels && !valid[k]) {
        out.map_start[k] = kOffChartGroupTexel;
        continue;
      }
      bool lit = false;
      for (size_t g = 0; g < groups; ++g) lit = lit || group_maps.at(g).at(k) != vec3(0.0f);
      if (!lit) continue;
      if (out.map_values.size() + groups >= kOffChartGroupTexel)
        throw std::length_error("soft texels: the light groups' caustic texels exceed 2^32 values");
      out.map_start[k] = uint32_t(out.map_values.size());
      for (size_t g = 0; g < groups; ++g) out.map_values.push_back(group_maps[g][k]);
    }
  }
  const auto& per_group = bake.radiosity.group_vertex_radiance;
  out.vertex_radiance.resize(baked.vertex_radiance.size());
  for (size_t m = 0; m < out.vertex_radiance.size(); ++m) {
    const size_t vertices = baked.vertex_radiance[m].size();
    if (vertices == 0) continue;
    out.vertex_radiance[m].resize(vertices * groups);
    for (size_t g = 0; g < groups; ++g)
      for (size_t v = 0; v < vertices; ++v) out.vertex_radiance[m][v * groups + g] = per_group[g][m].at(v);
  }
  const LightSources sources(baked.scene);
  const std::vector<int> of_source =
      light_group_of_sources(baked.scene, sources, bake.light_groups);
  for (size_t j = 0; j < direct.light_count(); ++j)
    out.light_group.push_back(of_source.at(direct.source_of(j)));
  if (sources.sky()) out.sky_group = of_source.back();
  return out;
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

// Each cell's gather rays (SoftTexelParams::box_rays_max): gather_rays times the box area of
// filter_radius over that of its narrowest node's box, rounded up, at most box_rays_max.
std::vector<int> rays_following_the_box(int width, int height, const std::vector<double>& weight,
                                        const std::vector<int>& radii,
                                        const SoftTexelParams& used) {
  const auto at = [width](int i, int j) { return size_t(j) * size_t(width) + size_t(i); };
  std::vector<int> rays(size_t(width) * size_t(height), used.gather_rays);
  const double widest = 2.0 * used.filter_radius + 1.0;
  for (int j = 0; j < height; ++j)
    for (int i = 0; i < width; ++i) {
      int narrowest = used.filter_radius;
      for (int b = j; b <= std::min(j + 1, height - 1); ++b)
        for (int a = i; a <= std::min(i + 1, width - 1); ++a)
          if (weight[at(a, b)] > 0.0) narrowest = std::min(narrowest, radii[at(a, b)]);
      const double side = widest / (2.0 * narrowest + 1.0);
      // The tolerance keeps a ratio that is a whole number in exact arithmetic (r = 1 against
      // R = 4: 9) from rounding up to the next.
      const int times = std::clamp(int(std::ceil(side * side - 1e-9)), 1, used.box_rays_max);
      rays[at(i, j)] = used.gather_rays * times;
    }
  return rays;
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
  if (!(p.game_gather_budget >= 0.0 && p.game_gather_budget <= 1e10))
    throw std::invalid_argument("soft texels: game_gather_budget = " +
                                std::to_string(p.game_gather_budget) + " is outside [0, 1e10]");
  out_of_range("dilation_rings", p.dilation_rings, 0, 64);
  out_of_range("regather_rays", p.regather_rays, 0, 4096);
  out_of_range("box_rays_max", p.box_rays_max, 1, 64);
  if (!(p.regather_distance >= 0.0f && p.regather_distance < 1e30f))
    throw std::invalid_argument("soft texels: regather_distance = " +
                                std::to_string(p.regather_distance) + " is not a distance");
}

SoftTexelParams soft_texel_choices(const SoftTexelParams& params, size_t touched_cells) {
  SoftTexelParams used = params;
  used.points_side = params.points_side > 0
                         ? params.points_side
                         : side_for_budget(kSoftPointsBudget, touched_cells, 1, 8);
  if (params.filter_radius > 0)
    used.filter_radius = std::max(1, params.filter_radius / used.points_side);
  if (params.points_side == 0 && used.points_side >= 2 && params.gather_rays > 0 &&
      params.game_gather_budget > 0.0) {
    // Game densities: few texels, each wide; the rays a point from their own budget.
    const double points = double(touched_cells) * used.points_side * used.points_side;
    const int rays =
        int(std::min(params.game_gather_budget / points, double(kSoftMaxGatherRays)));
    used.gather_rays = std::max(params.gather_rays, rays);
    used.filter_radius = std::min(used.filter_radius, 1);
    // The plain mean: a slope from 5 x 5 nodes is too noisy, and its noise shows as steps at
    // seams (a floor of three UV islands at 10 texels/m: 1.21x its interior gradient in
    // three.js against 1.16x, the limit 1.2; the Cornell box's error at 10 and 20
    // texels/m 3.07 and 2.10% with the moved mean, 3.22 and 2.20% without).
    used.filter_fit = ChartFit::mean;
  }
  return used;
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
  // Game densities are texels coarser than the automatic rule's (scene diagonal / 256) by half
  // again: a small scene at its automatic density (a few 10k cells) keeps the rule it was
  // measured with (studded_wall: the same error, 1.6x the bake's CPU s).
  SoftTexelParams asked = params;
  const float automatic = glm::length(scene_bounds(scene).extent()) / 256.0f;
  if (!(maps.texel_size > 1.5f * automatic)) asked.game_gather_budget = 0.0;
  const SoftTexelParams used = soft_texel_choices(asked, footprints.touched_cells());

  // Light groups (bake/light_groups.h): each group's map from the same points and gather rays,
  // one layer each (none for a bake without its groups' arrays: a partial one); the whole map
  // is then their sum, so a blend at weights 1 is the whole map.
  const size_t groups =
      bake.radiosity.group_vertex_radiance.size() == bake.light_groups.size() &&
              bake.illumination.group_radiance.size() == bake.light_groups.size()
          ? bake.light_groups.size()
          : 0;
  const size_t layers = std::max<size_t>(groups, 1);

  // The base: the vertex radiosity resampled exactly (lightmap.h).
  const TexelEstimator interpolate = [&](std::span<const FootprintSample> samples,
                                         std::span<vec3> values, size_t) {
    for (size_t s = 0; s < samples.size(); ++s)
      interpolated_radiosity(bake, surfaces, samples[s], groups, &values[s], samples.size());
  };
  std::vector<double> weight;
  const auto resample = [&] {
    FillTexelsParams fill;
    fill.rule = FootprintRule::quadrature;
    fill.stage = "soft light: resampling";
    return fill_texel_layers(footprints, layers, interpolate, fill, progress, &weight);
  };
  std::vector<std::vector<vec3>> layer_maps;

  if (params.gather_rays > 0) {
    // The correction: the gather's footprint mean minus the interpolation's at the very same
    // points, so it is the difference of two estimates of one mean however a border cuts the
    // footprint. Without groups, both from one pass over the points (layer 0 the gather's,
    // layer 1 the interpolation's: the bits of the two fills it replaced), then the difference;
    // light groups take each point's difference (signed_values: half the layers), and their
    // base is resampled after the filter, folded into the corrections node by node.
    // The gather reads the solution itself at its hits, not a map the bake may already hold.
    BakedScene baked = make_baked_scene(scene, bake);
    baked.soft_texels = nullptr;
    const Accel accel(baked.scene);
    const DirectLight direct(baked.scene, accel);
    // Freed once the gather is done (the groups' lit caustic texels: 48 B each for 4 groups).
    GatherGroups group_terms = groups > 0 ? gather_groups(baked, direct, bake) : GatherGroups{};
    GatherContext context{baked, accel, direct};
    if (groups > 0) context.groups = &group_terms;
    context.regather_distance = params.regather_distance;
    context.regather_rays = params.regather_rays;
    std::atomic<uint64_t> gather_rays{0}, shadow_rays{0};
    FillTexelsParams fill;
    fill.rule = FootprintRule::stratified;
    fill.side = used.points_side;
    fill.seed = hash_seed(params.seed, 0x50f7);
    fill.stage = "soft light: final gather";
    fill.plane_fit_at_borders = false;  // noisy: see FillTexelsParams
    fill.signed_values = groups > 0;
    // The nodes' weights (the resampling's) and box radii first: cells whose boxes are narrow
    // gather more rays (box_rays_max).
    if (groups == 0) {
      layer_maps = resample();
    } else {
      // The nodes' weights alone (the resampling's, from its points without their values), so
      // the corrections are filtered before the base is resampled and each node's base goes
      // straight into its layers below: the groups' base maps are never held beside their
      // corrections (4 groups: 4 maps, 50 MB for the bench's room). One more pass over the
      // quadrature points.
      FillTexelsParams areas;
      areas.rule = FootprintRule::quadrature;
      areas.stage = "soft light: texel areas";
      areas.plane_fit_at_borders = false;  // the weights do not depend on it
      weight.assign(texels, 0.0);
      fill_texel_layers_into(
          footprints, 1, [](std::span<const FootprintSample>, std::span<vec3>, size_t) {},
          areas, [&](size_t node, std::span<const vec3>, double w) { weight[node] = w; },
          progress);
    }
    std::atomic<uint64_t> distance_rays{0};
    const std::vector<int> radii = filter_radii(footprints, surfaces, accel, maps, weight, used,
                                                fill, progress, distance_rays);
    const std::vector<int> cell_rays =
        rays_following_the_box(width, height, weight, radii, used);
    const uint64_t scramble = hash_seed(params.seed, 0x57a7);
    // A cell row's points gathered together, their rays in waves (gather_waves.h).
    const TexelRowEstimator gather_row = [&](std::span<const FootprintSample> samples,
                                             std::span<const size_t> first,
                                             std::span<const size_t> cells,
                                             std::span<vec3> values) {
      const size_t per_point = groups > 0 ? groups : 2;  // layers
      std::vector<GatherPoint> points(samples.size());
      for (size_t c = 0; c < cells.size(); ++c) {
        const size_t cell = cells[c];
        const SampleCell stratum =
            interleaved_stratum(int(cell % size_t(width)), int(cell / size_t(width)),
                                used.strata_levels, scramble);
        for (size_t s = first[c]; s < first[c + 1]; ++s) {
          points[s].x = receiver_at_sample(*surfaces[samples[s].mesh], samples[s]);
          points[s].stream = hash_seed(fill.seed, cell, s - first[c]);
          points[s].cell = stratum;
        }
      }
      GatherCounts counts;
      std::vector<vec3> means(samples.size()), group_means(samples.size() * groups);
      // The cells' points gathered in groups of equal rays, then put back in order.
      std::vector<int> point_rays(samples.size());
      for (size_t c = 0; c < cells.size(); ++c)
        for (size_t s = first[c]; s < first[c + 1]; ++s) point_rays[s] = cell_rays[cells[c]];
      std::vector<int> counts_of = point_rays;
      std::sort(counts_of.begin(), counts_of.end());
      counts_of.erase(std::unique(counts_of.begin(), counts_of.end()), counts_of.end());
      if (counts_of.size() == 1) {
        gather_soft_light_waves(context, points, counts_of[0], means, counts, group_means);
      } else {
        for (const int rays : counts_of) {
          std::vector<GatherPoint> some;
          std::vector<size_t> index;
          for (size_t s = 0; s < samples.size(); ++s)
            if (point_rays[s] == rays) some.push_back(points[s]), index.push_back(s);
          std::vector<vec3> some_means(some.size()), some_groups(some.size() * groups);
          gather_soft_light_waves(context, some, rays, some_means, counts, some_groups);
          for (size_t n = 0; n < index.size(); ++n) {
            means[index[n]] = some_means[n];
            for (size_t g = 0; g < groups; ++g)
              group_means[index[n] * groups + g] = some_groups[n * groups + g];
          }
        }
      }
      std::vector<vec3> interpolated(layers);
      for (size_t c = 0; c < cells.size(); ++c) {
        const size_t n = first[c + 1] - first[c];
        vec3* cell_values = &values[per_point * first[c]];
        for (size_t s = 0; s < n; ++s) {
          const size_t point = first[c] + s;
          cell_values[s] = means[point];
          interpolated_radiosity(bake, surfaces, samples[point], groups, interpolated.data(), 1);
          if (groups == 0) cell_values[n + s] = interpolated[0];
          for (size_t g = 0; g < groups; ++g)
            cell_values[g * n + s] = group_means[point * groups + g] - interpolated[g];
        }
      }
      gather_rays += counts.rays;
      shadow_rays += counts.shadow;
    };
    std::vector<std::vector<vec3>> correction = fill_texel_layers(
        footprints, groups > 0 ? groups : 2, gather_row,
        fill, progress);
    group_terms = GatherGroups{};
    if (groups == 0) {
      for (size_t k = 0; k < texels; ++k) correction[0][k] -= correction[1][k];
      correction.resize(1);
    }
    std::vector<std::vector<vec3>*> smooth;
    for (std::vector<vec3>& layer : correction) smooth.push_back(&layer);
    chart_box_filter_in_place(width, height, smooth, weight, radii, used.filter_fit);
    // Soft light is never negative; the clamp only acts where the noise exceeds the value.
    const auto corrected = [](vec3 base, vec3 correction, double w) {
      return w > 0.0 ? glm::max(base + correction, vec3(0.0f)) : base;
    };
    if (groups == 0) {
      for (size_t k = 0; k < texels; ++k)
        layer_maps[0][k] = corrected(layer_maps[0][k], correction[0][k], weight[k]);
    } else {
      FillTexelsParams fill_base;
      fill_base.rule = FootprintRule::quadrature;
      fill_base.stage = "soft light: resampling";
      fill_texel_layers_into(
          footprints, groups, interpolate, fill_base,
          [&](size_t node, std::span<const vec3> base, double w) {
            for (size_t g = 0; g < groups; ++g)
              correction[g][node] = corrected(base[g], correction[g][node], w);
          },
          progress);
      layer_maps = std::move(correction);
    }
    out.gather_rays = gather_rays;
    out.shadow_rays = shadow_rays;
    out.distance_rays = distance_rays;
  } else {
    layer_maps = resample();
  }

  std::vector<uint8_t> filled(texels, 0);
  for (size_t k = 0; k < texels; ++k) filled[k] = weight[k] > 0.0 ? 1 : 0;
  for (std::vector<vec3>& map : layer_maps)
    dilate_texels(width, height, filled, map, params.dilation_rings);
  if (groups == 0) {
    out.radiance = std::move(layer_maps[0]);
  } else {
    out.radiance.assign(texels, vec3(0.0f));
    for (const std::vector<vec3>& map : layer_maps)
      for (size_t k = 0; k < texels; ++k) out.radiance[k] += map[k];
    out.group_radiance = std::move(layer_maps);
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace lb
