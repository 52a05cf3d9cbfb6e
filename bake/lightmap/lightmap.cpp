#include "bake/lightmap/lightmap.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <numeric>
#include <stdexcept>

#include "bake/accel.h"
#include "bake/transport/direct_light.h"
#include "bake/lightmap/shadow_plan.h"
#include "bake/lightmap/soft_texels.h"
#include "bake/lightmap/texel_footprint.h"
#include "bake/lightmap/texel_projection.h"
#include "bake/lightmap/unshadowed_light.h"
#include "bake/light_sources.h"
#include "bake/lightmap/texel_receiver.h"
#include "bake/sampling.h"

namespace lb {

namespace {

// Which of a cell's points trace a shadow ray (LightmapParams::shadow_side): one per
// shadow_side x shadow_side stratum of the cell, drawn at random among the points in it and
// weighted by their number, so the weighted sum still estimates the cell's; 0 for the others.
// Empty when every point traces.
std::vector<float> shadow_ray_weights(std::span<const FootprintSample> samples, int shadow_side,
                                      uint64_t seed, size_t cell) {
  if (shadow_side <= 0) return {};
  const size_t strata = size_t(shadow_side) * size_t(shadow_side);
  std::vector<uint32_t> stratum(samples.size()), count(strata, 0);
  for (size_t s = 0; s < samples.size(); ++s) {
    const glm::ivec2 c = glm::min(glm::ivec2(samples[s].in_cell * float(shadow_side)),
                                  glm::ivec2(shadow_side - 1));
    stratum[s] = uint32_t(glm::max(c.y, 0) * shadow_side + glm::max(c.x, 0));
    ++count[stratum[s]];
  }
  Rng rng(hash_seed(seed, cell, 0x5ad0e));
  std::vector<uint32_t> pick(strata);
  for (size_t k = 0; k < strata; ++k) pick[k] = count[k] ? rng.next_u32() % count[k] : 0;
  std::vector<float> weight(samples.size(), 0.0f);
  std::vector<uint32_t> seen(strata, 0);
  for (size_t s = 0; s < samples.size(); ++s)
    if (seen[stratum[s]]++ == pick[stratum[s]]) weight[s] = float(count[stratum[s]]);
  return weight;
}

// The pilot's traced points of a cell, kept so that a cell that traces again counts them too
// (unbiased samples of the same cell, as its own): the point's index among the cell's, whether
// its ray was blocked, and its unshadowed estimate times its weight.
struct PilotRay {
  uint32_t sample = 0;
  bool blocked = false;
  vec3 value{0.0f};
};
using PilotRays = std::vector<std::vector<PilotRay>>;

// The direct term's two estimates at a fill's points, as its layers in this order (those
// asked for): `shadowed`, one shadow ray per point (per chosen point with a shadow side,
// above) to a light chosen by HQ mode's rule at the cell's direct_light_samples; `unshadowed`,
// the same light samples with every shadow ray taken as unblocked (the ratio estimator's
// denominator, header). Both in one fill sample the light once for the two.
struct DirectLayers {
  bool shadowed = true;
  bool unshadowed = false;
};

// `plan` (may be null: every cell `shadow_side`) sets each cell's side and mode. `pilot` (may
// be null): with `outcome` (the pilot), each cell's rays go into both; without, the cells that
// trace add the pilot's points to their own, weighted by their numbers.
TexelEstimator direct_estimator(const DirectLight& direct, const std::vector<const Mesh*>& surfaces,
                                uint64_t seed, int shadow_side, const ShadowPlan* plan,
                                std::atomic<uint64_t>& shadow_rays, std::atomic<uint64_t>& points,
                                DirectLayers layers = {}, PilotOutcome* outcome = nullptr,
                                PilotRays* pilot = nullptr) {
  return [&direct, &surfaces, seed, shadow_side, plan, &shadow_rays, &points, layers, outcome,
          pilot](std::span<const FootprintSample> samples, std::span<vec3> values, size_t cell) {
    const size_t n = samples.size();
    const std::span<vec3> shadowed = layers.shadowed ? values.first(n) : std::span<vec3>{};
    const std::span<vec3> unshadowed = layers.unshadowed ? values.last(n) : std::span<vec3>{};
    const int side = plan ? int(plan->side[cell]) : shadow_side;
    const ShadowPlan::Mode mode = plan ? plan->mode[cell] : ShadowPlan::kTrace;
    const std::vector<float> weight = shadow_ray_weights(samples, side, seed, cell);
    const size_t traced = weight.empty() ? n
                                         : size_t(std::count_if(weight.begin(), weight.end(),
                                                                [](float w) { return w > 0.0f; }));
    const bool rays_here = layers.shadowed && mode == ShadowPlan::kTrace;
    if (rays_here) points += traced;
    // A dark verdict's points are 0 shadowed; only the denominator samples them.
    const bool dark = mode == ShadowPlan::kDark;
    std::vector<DirectLightSample> light_samples;
    direct_light_samples(seed, cell, traced, light_samples);
    uint32_t rays = 0, lit = 0;
    uint8_t found = 0;
    std::vector<PilotRay>* kept = pilot && outcome ? &(*pilot)[cell] : nullptr;
    if (kept) kept->clear();
    for (size_t s = 0, k = 0; s < n; ++s) {
      if ((!weight.empty() && weight[s] == 0.0f) || (dark && !layers.unshadowed)) {
        for (std::span<vec3> layer : {shadowed, unshadowed})
          if (!layer.empty()) layer[s] = vec3(0.0f);
        continue;
      }
      const ReceiverPoint x = receiver_at_sample(*surfaces[samples[s].mesh], samples[s]);
      const auto [u_select, u_light] = light_samples[k++];
      Ray shadow_ray;
      const DeferredEstimate e = direct.sample_one_light(x, u_select, u_light, shadow_ray);
      vec3 value = e.value;
      bool blocked = false;
      if (rays_here && e.shadow_ray) {
        ++rays;
        blocked = direct.accel().occluded(shadow_ray);
        found |= blocked ? PilotOutcome::kSomeBlocked : PilotOutcome::kSomeLit;
        lit += !blocked;
      }
      if (!weight.empty()) value *= weight[s];
      if (kept) kept->push_back({uint32_t(s), blocked, value});
      if (!shadowed.empty()) shadowed[s] = blocked || dark ? vec3(0.0f) : value;
      if (!unshadowed.empty()) unshadowed[s] = value;
    }
    if (pilot && !outcome && mode == ShadowPlan::kTrace && !(*pilot)[cell].empty()) {
      const std::vector<PilotRay>& before = (*pilot)[cell];
      const float own = float(traced) / float(traced + before.size());
      for (const bool blocked_counts : {true, false}) {
        const std::span<vec3> layer = blocked_counts ? shadowed : unshadowed;
        if (layer.empty()) continue;
        for (vec3& v : layer) v *= own;
        for (const PilotRay& p : before)
          if (!(blocked_counts && p.blocked)) layer[p.sample] += (1.0f - own) * p.value;
      }
    }
    shadow_rays += rays;
    if (outcome)
      outcome->found[cell] = found, outcome->rays[cell] = rays, outcome->lit[cell] = lit;
  };
}

// Per node, the area of surface under its tent that is not hidden under other geometry (m^2,
// quadrature: exact up to the footprint's clipping).
std::vector<double> visible_node_area(const TexelFootprints& footprints,
                                      const std::vector<std::vector<uint8_t>>& hidden,
                                      const Progress& progress) {
  FillTexelsParams params;
  params.stage = "lightmap: visible surface";
  params.hidden_triangles = &hidden;
  std::vector<double> area;
  fill_texels(
      footprints,
      [](std::span<const FootprintSample>, std::span<vec3> values, size_t) {
        std::fill(values.begin(), values.end(), vec3(1.0f));
      },
      params, progress, &area);
  return area;
}

// The atlas's nodes with visible surface under them: the direct term's texels.
std::vector<uint8_t> covered_nodes(const IlluminationMaps& maps, const std::vector<double>& visible) {
  std::vector<uint8_t> covered(visible.size(), 0);
  for (size_t k = 0; k < covered.size(); ++k)
    covered[k] = k < maps.valid.size() && maps.valid[k] && visible[k] > 0.0;
  return covered;
}

SoftTexelParams resampling_only(const LightmapParams& params) {
  SoftTexelParams soft;
  soft.gather_rays = 0;
  soft.seed = params.seed;
  return soft;
}

}  // namespace

const char* to_string(LightmapContents contents) {
  return contents == LightmapContents::all ? "all" : "indirect";
}

LightmapContents parse_lightmap_contents(const std::string& text) {
  if (text == "indirect") return LightmapContents::indirect;
  if (text == "all") return LightmapContents::all;
  throw std::invalid_argument("--contents '" + text + "': expected 'indirect' or 'all'");
}

std::vector<const Mesh*> lightmap_surfaces(const Scene& scene, const BakeResult& bake,
                                           std::vector<Mesh>& storage) {
  const IlluminationMaps& maps = bake.illumination;
  std::vector<const Mesh*> surfaces(scene.meshes.size(), nullptr);
  storage.clear();
  storage.reserve(scene.meshes.size());  // pointers into it stay valid
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    if (m >= maps.lightmap_uvs.size() || maps.lightmap_uvs[m].empty()) continue;
    if (m < bake.radiosity.meshes.size()) {
      const Mesh& refined = bake.radiosity.meshes[m].mesh;
      if (!refined.positions.empty() && refined.lightmap_uvs.size() == refined.positions.size()) {
        surfaces[m] = &refined;
        continue;
      }
    }
    storage.push_back(mesh_with_lightmap(scene.meshes[m], maps, m));
    surfaces[m] = &storage.back();
  }
  return surfaces;
}

void direct_light_samples(uint64_t seed, size_t cell, size_t n,
                          std::vector<DirectLightSample>& out) {
  Rng rng(hash_seed(seed, cell, 0xd12ec7));
  std::vector<uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  for (size_t k = n; k > 1; --k) std::swap(order[k - 1], order[rng.next_u32() % k]);
  const int side = std::max(1, int(std::ceil(std::sqrt(double(n)))));
  out.resize(n);
  for (size_t s = 0; s < n; ++s) {
    const uint32_t k = order[s];
    const float u_select = (float(k) + rng.next_float()) / float(n);
    const vec2 u_point =
        (vec2(float(k % uint32_t(side)), float(k / uint32_t(side))) + rng.next_2d()) /
        float(side);
    out[s] = {u_select, glm::min(u_point, vec2(0.99999994f))};
  }
}

int direct_side_for(const LightmapParams& params, const TexelFootprints& footprints) {
  return params.direct_side > 0
             ? params.direct_side
             : side_for_budget(kDirectPointsBudget, footprints.touched_cells(), 4, 16);
}

Lightmap bake_lightmap(const Scene& scene, const BakeResult& bake, const LightmapParams& params,
                       const Progress& progress, const std::vector<vec3>* direct_given,
                       const std::vector<vec3>* unshadowed_given) {
  if (params.direct_side < 0 || params.direct_side > 64)
    throw std::invalid_argument("lightmap: direct_side = " + std::to_string(params.direct_side) +
                                " is outside [0, 64]");
  const auto start = std::chrono::steady_clock::now();
  const IlluminationMaps& maps = bake.illumination;
  Lightmap out;
  out.width = maps.width;
  out.height = maps.height;
  out.contents = params.contents;
  if (params.shard_count < 1 || params.shard < 0 || params.shard >= params.shard_count)
    throw std::invalid_argument("lightmap: shard " + std::to_string(params.shard) + " of " +
                                std::to_string(params.shard_count));
  const size_t texels = size_t(maps.width) * size_t(maps.height);
  out.direct_rows = {0, maps.height};
  if (texels == 0) return out;

  std::vector<Mesh> storage;
  const std::vector<const Mesh*> surfaces = lightmap_surfaces(scene, bake, storage);
  const TexelFootprints footprints(surfaces, maps.width, maps.height);
  const Accel accel(scene);
  const std::vector<std::vector<uint8_t>> hidden =
      params.skip_hidden_surface ? hidden_surface_triangles(surfaces, accel)
                                 : std::vector<std::vector<uint8_t>>{};
  const std::vector<double> visible = visible_node_area(footprints, hidden, progress);
  // The bake's soft-light texel map where it has one (the texels the viewer draws), else the
  // plain resampling of the vertex radiosity; kept on the atlas's valid nodes only.
  out.soft = bake.soft_texels.radiance.size() == texels
                 ? bake.soft_texels.radiance
                 : soft_light_texels(scene, bake, resampling_only(params), progress).radiance;
  for (size_t k = 0; k < texels; ++k)
    if (k >= maps.valid.size() || !maps.valid[k]) out.soft[k] = vec3(0.0f);
  // Surface under an open sheet (a lamp's back 1 cm off a ceiling) gets soft light round the
  // sheet's edges, a fall-off only the final gather resolves; without it (draft) the patches'
  // mean stood there, 3x Cycles' light under the Cornell box's lamp. So a node that sees only
  // such surface takes no soft light into the sum then (its direct light, shadow rays', stays).
  std::vector<uint8_t> soft_unresolved(texels, 0);
  if (params.skip_hidden_surface && bake.soft_texels.gather_rays == 0) {
    const std::vector<double> open = visible_node_area(
        footprints, hidden_surface_triangles(surfaces, accel, /*sheltered_hidden=*/true),
        progress);
    for (size_t k = 0; k < texels; ++k) soft_unresolved[k] = visible[k] > 0.0 && !(open[k] > 0.0);
  }
  const DirectLight direct_light(scene, accel);
  // The direct term's points (stratified, hidden surface dropped): its shards' and the
  // projection's.
  FillTexelsParams fill;
  fill.rule = FootprintRule::stratified;
  fill.side = direct_side_for(params, footprints);
  // A shadow ray from some of the points only (shadow_side < side), or from every one (0).
  const int shadow_side =
      params.shadow_side > 0 && params.shadow_side < fill.side ? params.shadow_side : 0;
  fill.seed = hash_seed(params.seed, 0xd12ec7);
  fill.stage = "lightmap: direct light";
  fill.plane_fit_at_borders = false;  // noisy: see FillTexelsParams; the projection does better
  fill.hidden_triangles = &hidden;
  ShadowPlan shadow_plan;              // adaptive shadow rays: per cell
  const ShadowPlan* plan = nullptr;    // &shadow_plan once made (null: every cell shadow_side)
  PilotRays pilot_rays;                // the pilot's points, counted again where cells trace
  const LightSources sources(scene);
  const bool ratio_estimator =
      params.ratio_estimator && emitting_triangle_count(sources) <= kMaxAnalyticTriangles;
  std::vector<vec3> sampled;  // the ratio estimator's denominator: the unshadowed light, sampled
  std::atomic<uint64_t> shadow_rays{0}, points{0};
  // Adaptive shadow rays: a pilot over the whole map plans every cell. A shard runs it whole
  // too, so its rows get the unsharded plan; a merge whose shards carry no denominator runs it
  // again, as that denominator reads the plan and the pilot's points (a ray or so a cell:
  // cheap to repeat). A shard's counts leave its repeat of the pilot out.
  const auto plan_shadow_rays = [&] {
    if (shadow_side <= 0 || !params.adaptive_shadow_rays) return;
    const int pilot_side = std::max(1, shadow_side / 2);
    PilotOutcome outcome(footprints.cell_count());
    pilot_rays.resize(footprints.cell_count());
    FillTexelsParams pilot = fill;
    pilot.rows.reset();
    pilot.stage = "lightmap: direct light, pilot";
    std::atomic<uint64_t> pilot_rays_cast{0}, pilot_points{0};
    fill_texels(footprints,
                direct_estimator(direct_light, surfaces, fill.seed, pilot_side, nullptr,
                                 pilot_rays_cast, pilot_points, {}, &outcome, &pilot_rays),
                pilot, progress);
    if (!fill.rows) shadow_rays += pilot_rays_cast, points += pilot_points;
    shadow_plan = adaptive_shadow_plan(footprints.width(), footprints.height(), outcome,
                                       pilot_side, shadow_side, fill.side);
    plan = &shadow_plan;
  };
  if (params.contents == LightmapContents::all && direct_given) {
    if (direct_given->size() != texels)
      throw std::invalid_argument("lightmap: the direct term given has " +
                                  std::to_string(direct_given->size()) + " texels, the atlas " +
                                  std::to_string(texels));
    out.direct = *direct_given;
    if (unshadowed_given && ratio_estimator) {  // the shards' own, at the same points
      if (unshadowed_given->size() != texels)
        throw std::invalid_argument("lightmap: the unshadowed light given has " +
                                    std::to_string(unshadowed_given->size()) +
                                    " texels, the atlas " + std::to_string(texels));
      sampled = *unshadowed_given;
    } else {
      plan_shadow_rays();
    }
  } else if (params.contents == LightmapContents::all) {
    if (params.shard_count > 1)
      fill.rows = partition_texel_rows(texel_row_work(footprints, &hidden),
                                       params.shard_count)[size_t(params.shard)];
    out.direct_rows = fill.rows.value_or(out.direct_rows);
    plan_shadow_rays();
    // The denominator from the same fill; a shard's rows of it go to the merge.
    const DirectLayers layers{.shadowed = true, .unshadowed = ratio_estimator};
    std::vector<std::vector<vec3>> filled = fill_texel_layers(
        footprints, layers.unshadowed ? 2 : 1,
        direct_estimator(direct_light, surfaces, fill.seed, shadow_side, plan, shadow_rays, points,
                         layers, nullptr, plan ? &pilot_rays : nullptr),
        fill, progress);
    out.direct = std::move(filled[0]);
    if (layers.unshadowed) sampled = std::move(filled[1]);
    if (out.direct_rows.count() != maps.height) out.direct_unshadowed = std::move(sampled);
    out.shadow_rays = shadow_rays;
    out.direct_points = points;
  }
  // A shard's direct term is a part: the ratio and the projection act once it is joined.
  const bool whole_direct = !out.direct.empty() && out.direct_rows.count() == maps.height;
  std::vector<vec3> direct_term = out.direct;
  out.ratio_estimator = whole_direct && ratio_estimator;
  if (out.ratio_estimator) {
    if (sampled.empty()) {  // the direct term given (joined shards): sample it here
      std::atomic<uint64_t> no_rays{0}, no_points{0};
      fill.stage = "lightmap: unshadowed light, sampled";
      sampled = fill_texels(footprints,
                            direct_estimator(direct_light, surfaces, fill.seed, shadow_side, plan,
                                             no_rays, no_points,
                                             {.shadowed = false, .unshadowed = true}, nullptr,
                                             plan ? &pilot_rays : nullptr),
                            fill, progress);
    }
    // The closed form is smooth over a cell: a quarter of the points integrates it (it cost
    // twice the shadow rays' time at all of them on the Cornell box).
    FillTexelsParams smooth = fill;
    smooth.stage = "lightmap: unshadowed light, closed form";
    smooth.side = std::max(2, fill.side / 2);
    const std::vector<vec3> exact = fill_texels(
        footprints,
        [&](std::span<const FootprintSample> samples, std::span<vec3> values, size_t) {
          for (size_t s = 0; s < samples.size(); ++s)
            values[s] = unshadowed_direct(
                scene, sources, receiver_at_sample(*surfaces[samples[s].mesh], samples[s]));
        },
        smooth, progress);
    for (size_t k = 0; k < texels; ++k)
      for (int c = 0; c < 3; ++c)
        if (sampled[k][c] > 0.0f)
          direct_term[k][c] = float(double(exact[k][c]) * out.direct[k][c] / sampled[k][c]);
    if (params.denoise_direct) {
      std::vector<vec3> share(texels, vec3(1.0f));
      std::vector<uint8_t> penumbra(texels, 0);  // a share of 0 or 1 is exact: no noise
      for (size_t k = 0; k < texels; ++k)
        for (int c = 0; c < 3; ++c)
          if (exact[k][c] > 0.0f) {
            share[k][c] = direct_term[k][c] / exact[k][c];
            penumbra[k] |= share[k][c] > 0.0f && share[k][c] < 1.0f;
          }
      // Each chart group keeps the direct term's energy, sum(exact x share), not the share's.
      share = denoise_texels(out.width, out.height, covered_nodes(maps, visible), share,
                             &out.denoise, &exact, &penumbra);
      for (size_t k = 0; k < texels; ++k) direct_term[k] = exact[k] * share[k];
      out.denoised = true;
    }
  } else if (whole_direct && params.denoise_direct) {
    direct_term = denoise_texels(out.width, out.height, covered_nodes(maps, visible), direct_term,
                                 &out.denoise);
    out.denoised = true;
  }
  if (whole_direct && params.project_direct && fill.side >= kProjectFromSide)
    direct_term = project_to_bilinear(footprints, fill, direct_term,
                                      {.ridge = params.projection_ridge}, progress, &out.projection);
  out.direct_term = std::move(direct_term);

  // The sum on the atlas's valid nodes (the caustic map's own dilation is replaced). A node
  // with no visible surface under its footprint (wholly under a block or inside a wall: shut in
  // by opaque geometry, which is what `hidden` means) holds 0, the light that reaches it; its
  // terms there would be the interpolation's guesses from the open surface around. Such nodes
  // are charts of their own (contact_conform.h), so no visible texel reads them.
  out.radiance.assign(texels, vec3(0.0f));
  std::vector<uint8_t> valid(texels, 0);
  for (size_t k = 0; k < texels; ++k) {
    if (k >= maps.valid.size() || !maps.valid[k]) continue;
    valid[k] = 1;
    if (visible[k] <= 0.0) continue;
    out.radiance[k] = (k < maps.radiance.size() ? maps.radiance[k] : vec3(0.0f)) +
                      (soft_unresolved[k] ? vec3(0.0f) : out.soft[k]) +
                      (out.direct_term.empty() ? vec3(0.0f) : out.direct_term[k]);
  }
  if (params.stitch_seams)
    out.seams = stitch_seams(atlas_seams(scene, maps), out.radiance, params.seam_weight);
  dilate_texels(out.width, out.height, valid, out.radiance, params.dilation_rings);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace lb
