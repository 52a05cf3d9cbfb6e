#include "bake/pipeline/bake_settings.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <type_traits>

#include "bake/illumination/light_rays.h"
#include "bake/lightmap/interleaved_strata.h"
#include "bake/work_limits.h"

namespace lb {

namespace {

constexpr double kUnbounded = std::numeric_limits<double>::infinity();
constexpr double kLargeCount = 1e12;
// Seeds travel through doubles (scene files, the panel): whole numbers up to 2^53 are exact.
constexpr double kLargestSeed = 9007199254740992.0;

constexpr const char* kGeneral = "Bake";
constexpr const char* kPass1 = "Pass 1: illumination maps";
constexpr const char* kPass2 = "Pass 2: radiosity";
constexpr const char* kSoft = "Soft-light texel map";

using Field = BakeSetting::Field;

// Ranges are those the passes' own checks enforce (check_illumination_params,
// check_radiosity_params, check_soft_texel_params), so a value refused here names the key
// before any work starts, and one accepted here is never refused later.
const std::array kSettings{
    BakeSetting{"seed", kGeneral, "Random seed of both passes", 0, kLargestSeed,
                [](BakeParams& p) -> Field { return &p.seed; }},
    // Pass 1.
    BakeSetting{"feeler_zones", kPass1, "Feeler rays on an N x N grid of zones per light", 1,
                kMaxFeelerGridSide,
                [](BakeParams& p) -> Field { return &p.illumination.feeler_zones; }},
    BakeSetting{"feelers_per_zone_side", kPass1, "Feelers per zone: N x N", 1, 64,
                [](BakeParams& p) -> Field { return &p.illumination.feelers_per_zone_side; }},
    BakeSetting{"aimed_feelers_side", kPass1,
                "Feelers aimed at each specular mesh from each light: N x N", 0, 256,
                [](BakeParams& p) -> Field { return &p.illumination.aimed_feelers_side; }},
    BakeSetting{"subzones_side", kPass1,
                "Sub-zones per zone: N x N, each with a feeler (1 = the paper's single level)", 1,
                kMaxFeelerGridSide,
                [](BakeParams& p) -> Field { return &p.illumination.subzones_side; }},
    BakeSetting{
        "rays_per_zone_side", kPass1, "Dense rays per traced zone: N x N", 1, kMaxRaysPerZoneSide,
        [](BakeParams& p) -> Field { return &p.illumination.rays_per_zone_side; }, true, true},
    BakeSetting{"caustic_filter", kPass1,
                "Density-estimation filter of the caustic map (off: the raw splat)", 0, 1,
                [](BakeParams& p) -> Field { return &p.illumination.density_filter; }},
    BakeSetting{"caustic_filter_deposits", kPass1,
                "Density filter: deposits each node's kernel gathers (more = smoother)", 1, 1e6,
                [](BakeParams& p) -> Field { return &p.illumination.filter_deposits; }},
    BakeSetting{"caustic_filter_radius", kPass1, "Density filter: largest kernel radius, texels", 1,
                64, [](BakeParams& p) -> Field { return &p.illumination.filter_max_radius; }},
    BakeSetting{"pilot_texels", kPass1,
                "Caustic pilot: finer texels on meshes under dense caustics, from a pilot trace "
                "at 1/pilot_divisor^2 of the rays",
                0, 1, [](BakeParams& p) -> Field { return &p.illumination.pilot_texels; }},
    BakeSetting{"pilot_divisor", kPass1, "Caustic pilot: rays per sub-zone side divided by this",
                1, 64, [](BakeParams& p) -> Field { return &p.illumination.pilot_divisor; }},
    BakeSetting{"pilot_skips_filter", kPass1,
                "The density filter leaves the meshes whose texels the pilot refined", 0, 1,
                [](BakeParams& p) -> Field { return &p.illumination.pilot_skips_filter; }},
    BakeSetting{"sky_directions_side", kPass1, "The sky's caustic directions: N x N", 1, 64,
                [](BakeParams& p) -> Field { return &p.illumination.sky_directions_side; }, true,
                true},
    BakeSetting{"caustic_max_depth", kPass1, "Specular bounces per illumination ray", 1, 1000,
                [](BakeParams& p) -> Field { return &p.illumination.max_depth; }},
    BakeSetting{"roulette_depth", kPass1, "Bounces before Russian roulette starts", 0, 1000,
                [](BakeParams& p) -> Field { return &p.illumination.roulette_depth; }},
    BakeSetting{"texel_size", kPass1, "Lightmap texel edge, metres (0 = automatic)", 0, kUnbounded,
                [](BakeParams& p) -> Field { return &p.illumination.texel_size; }, true, false},
    BakeSetting{"atlas_max_size", kPass1, "Largest atlas edge, texels", 16, 16384,
                [](BakeParams& p) -> Field { return &p.illumination.atlas_max_size; }},
    BakeSetting{"atlas_padding", kPass1,
                "Texels between charts (mip level k needs 2^k: 8 keeps 3 levels apart)", 2, 64,
                [](BakeParams& p) -> Field { return &p.illumination.atlas_padding; }},
    BakeSetting{"generate_lightmap_uvs", kPass1,
                "Unwrap meshes that bring their own lightmap UVs too (otherwise kept when they "
                "neither fold nor overlap)",
                0, 1, [](BakeParams& p) -> Field { return &p.illumination.generate_lightmap_uvs; }},
    BakeSetting{"chart_angle_deg", kPass1,
                "Chart growth: largest angle to the seed face's normal, degrees", 0.1, 89.9,
                [](BakeParams& p) -> Field { return &p.illumination.chart_angle_deg; }},
    BakeSetting{"trace_all_zones", kPass1, "Diagnostics: dense rays in every zone (no feelers)", 0,
                1, [](BakeParams& p) -> Field { return &p.illumination.trace_all_zones; }},
    BakeSetting{"directional", kPass1,
                "Directional maps: the caustic and soft-light maps' L1 bands (per texel, how "
                "their light changes as a bump map tilts the normal; docs/export.md)",
                0, 1, [](BakeParams& p) -> Field { return &p.illumination.directional; }},
    BakeSetting{"stratified", kPass1,
                "Jittered grids of directions (off: independent random directions)", 0, 1,
                [](BakeParams& p) -> Field { return &p.illumination.stratified; }},
    // Pass 2.
    BakeSetting{"patch_size", kPass2,
                "Radiosity patch edge, metres (0 = automatic: ~16 patches along the largest wall)",
                0, kUnbounded, [](BakeParams& p) -> Field { return &p.radiosity.patch_size; }, true,
                true},
    BakeSetting{"ray_budget", kPass2, "Total radiosity rays (about)", 1,
                double(kMaxRadiosityRayBudget),
                [](BakeParams& p) -> Field { return &p.radiosity.ray_budget; }, true, true},
    BakeSetting{"min_rays_per_shot", kPass2, "Fewest rays in one shot", 1, kLargeCount,
                [](BakeParams& p) -> Field { return &p.radiosity.min_rays_per_shot; }},
    BakeSetting{"convergence", kPass2,
                "Stop when unsent power < this fraction of the emitted power", 0, 1,
                [](BakeParams& p) -> Field { return &p.radiosity.convergence; }},
    BakeSetting{"max_shots", kPass2, "Hard cap on shots (0 = max(100000, 128 x patches))", 0,
                kLargeCount, [](BakeParams& p) -> Field { return &p.radiosity.max_shots; }},
    BakeSetting{"max_rays", kPass2, "Hard cap on rays (0 = 4 x budget + what the shot cap needs)",
                0, 4.0 * double(kMaxRadiosityRayBudget),
                [](BakeParams& p) -> Field { return &p.radiosity.max_rays; }},
    BakeSetting{"max_specular_depth", kPass2, "Specular bounces per radiosity ray", 0, 1000,
                [](BakeParams& p) -> Field { return &p.radiosity.max_specular_depth; }},
    BakeSetting{"emitters_reflect", kPass2, "Diffuse emitters also receive and reflect light", 0, 1,
                [](BakeParams& p) -> Field { return &p.radiosity.emitters_reflect; }},
    BakeSetting{"contact_cuts", kPass2,
                "Cut patches along contacts with other geometry (off only to measure the leak)", 0,
                1, [](BakeParams& p) -> Field { return &p.radiosity.contact_cuts; }},
    // The soft-light texel map.
    BakeSetting{"soft_gather_rays", kSoft,
                "Final-gather rays per texel point (0 = resample the vertex radiosity)", 0, 4096,
                [](BakeParams& p) -> Field { return &p.soft_texels.gather_rays; }, true, true},
    BakeSetting{"soft_points_side", kSoft,
                "Gather points per texel: N x N (0: automatic, more where texels are few)", 0, 8,
                [](BakeParams& p) -> Field { return &p.soft_texels.points_side; }},
    BakeSetting{"soft_filter_radius", kSoft,
                "Largest half-width in texels of the filter over the gather's correction", 0, 16,
                [](BakeParams& p) -> Field { return &p.soft_texels.filter_radius; }},
    BakeSetting{"soft_filter_reach", kSoft,
                "The filter's half-width at most this times a texel's harmonic mean distance "
                "to the surfaces around it (0 = always the radius)",
                0, 100, [](BakeParams& p) -> Field { return &p.soft_texels.filter_reach; }},
    BakeSetting{"soft_strata_levels", kSoft,
                "Gather directions interleaved over 4^N sub-squares across neighbouring texels",
                0, kMaxStrataLevels,
                [](BakeParams& p) -> Field { return &p.soft_texels.strata_levels; }},
    BakeSetting{"soft_box_rays_max", kSoft,
                "Texels whose filter is narrower than the radius gather more rays, up to this "
                "many times (1 = the same rays everywhere)",
                1, 64, [](BakeParams& p) -> Field { return &p.soft_texels.box_rays_max; }},
    BakeSetting{"soft_dilation_rings", kSoft, "Texel rings filled around each chart", 0, 64,
                [](BakeParams& p) -> Field { return &p.soft_texels.dilation_rings; }},
};

std::string format_value(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.10g", value);
  return text;
}

std::string kebab(const char* key) {
  std::string name = key;
  std::replace(name.begin(), name.end(), '_', '-');
  return name;
}

}  // namespace

bool BakeSetting::is_boolean() const {
  BakeParams probe;
  return std::holds_alternative<bool*>(field(probe));
}

bool BakeSetting::is_integer() const {
  BakeParams probe;
  const Field f = field(probe);
  return std::holds_alternative<int*>(f) || std::holds_alternative<uint64_t*>(f);
}

double BakeSetting::get(const BakeParams& params) const {
  // The accessor only hands out a pointer; reading through it leaves `params` as it was.
  return std::visit([](auto* value) { return double(*value); },
                    field(const_cast<BakeParams&>(params)));
}

std::string BakeSetting::check(double value) const {
  if (!(value >= min && value <= max))
    return format_value(value) + " is outside [" + format_value(min) + ", " + format_value(max) +
           "]";
  if ((is_integer() || is_boolean()) && value != std::floor(value))
    return format_value(value) + " is not a whole number";
  return {};
}

void BakeSetting::set(BakeParams& params, double value) const {
  if (const std::string problem = check(value); !problem.empty())
    throw std::invalid_argument(std::string(key) + ": " + problem);
  std::visit([value](auto* target) { *target = std::remove_pointer_t<decltype(target)>(value); },
             field(params));
}

std::string BakeSetting::option_name() const {
  return "--" + kebab(key);
}

std::string BakeSetting::negative_option_name() const {
  return "--no-" + kebab(key);
}

std::span<const BakeSetting> bake_settings() {
  return kSettings;
}

const BakeSetting* find_bake_setting(std::string_view key) {
  for (const BakeSetting& setting : kSettings)
    if (key == setting.key) return &setting;
  return nullptr;
}

std::string RetiredBakeSetting::check(double given) const {
  // A float setting: 0.05 in a scene file is the float the manifest recorded as 0.05000000075.
  if (boolean ? given == value : float(given) == float(value)) return {};
  auto text = [this](double v) {
    return boolean ? std::string(v != 0.0 ? "true" : "false") : format_value(v);
  };
  return text(given) +
         ": no longer a bake setting; each light chooses where its pass-1 rays start (its "
         "mesh's caustic_origins, \"centre\" or \"area\"), and only " +
         text(value) + ", what the automatic choice does, is read";
}

const RetiredBakeSetting* find_retired_bake_setting(std::string_view key) {
  static const RetiredBakeSetting kRetired[] = {
      {"origins_over_light", 0.0, true},
      {"centre_origin_max_angle", double(illumination::kCentreOriginMaxAngle), false},
  };
  for (const RetiredBakeSetting& retired : kRetired)
    if (key == retired.key) return &retired;
  return nullptr;
}

void apply_scene_bake_settings(const Scene& scene, BakeParams& params) {
  for (const Scene::BakeSettingValue& file : scene.bake_settings) {
    if (const RetiredBakeSetting* retired = find_retired_bake_setting(file.key)) {
      if (const std::string problem = retired->check(file.value); !problem.empty())
        throw std::invalid_argument(file.where + ": " + problem);
      continue;
    }
    const BakeSetting* setting = find_bake_setting(file.key);
    if (!setting)
      throw std::invalid_argument(file.where +
                                  ": unknown bake setting (`lightbake bake --help` "
                                  "lists them, as options)");
    if (const std::string problem = setting->check(file.value); !problem.empty())
      throw std::invalid_argument(file.where + ": " + problem);
    setting->set(params, file.value);
  }
}

BakeParams resolve_bake_params(const Scene& scene, const BakeSettingsRequest& request) {
  BakeParams params;
  if (request.like) {
    params = *request.like;
  } else {
    apply_quality(scene, choose_quality(scene, std::nullopt), params);
    apply_scene_bake_settings(scene, params);
  }
  if (request.quality) apply_quality(scene, *request.quality, params);
  for (const GivenSetting& given : request.given) given.setting->set(params, given.value);
  return params;
}

}  // namespace lb
