// `lightbake bake SCENE -o DIR`: run both bake passes and save them as a bake directory
// (bake/pipeline/bake_io.h). The options bind BakeParams; Ctrl-C cancels cleanly (nothing is
// written), as does any error. A folder that is not a previous bake is refused before baking.

#include <cstdio>
#include <string>

#include "app/cli_parse.h"
#include "app/commands.h"
#include "app/console_progress.h"
#include "app/load.h"
#include "app/output_path.h"
#include "app/thread_option.h"
#include "bake/pipeline/bake.h"
#include "bake/pipeline/bake_io.h"
#include "bake/work_limits.h"

namespace lb::app {

namespace {

struct BakeOptions {
  std::string scene_path;
  std::string output_dir = "bake";
  BakeParams params;
  std::optional<Quality> quality;  // --quality, else the scene file's
  // The settings a quality level sets that were also given one by one (they win over a scene
  // file's level; --quality itself excludes them).
  bool patch_size_given = false, ray_budget_given = false, caustic_rays_given = false;
  bool texel_size_given = false;
  bool force = false;
  bool quiet = false;
};

// The bake's settings: the quality level's, then what was given one by one.
BakeParams resolve_params(const Scene& scene, const BakeOptions& options) {
  BakeParams params = options.params;
  apply_quality(scene, choose_quality(scene, options.quality), params);
  const BakeParams& given = options.params;
  if (options.patch_size_given) params.radiosity.patch_size = given.radiosity.patch_size;
  if (options.ray_budget_given) params.radiosity.ray_budget = given.radiosity.ray_budget;
  if (options.caustic_rays_given)
    params.illumination.rays_per_zone_side = given.illumination.rays_per_zone_side;
  if (options.texel_size_given) params.illumination.texel_size = given.illumination.texel_size;
  return params;
}

void print_summary(const BakeResult& bake, const std::string& directory) {
  const IlluminationStats& i = bake.illumination.stats;
  const RadiosityStats& r = bake.radiosity.stats;
  std::printf(
      "illumination  %dx%d atlas at %.4g texels/m, %llu feeler + %llu dense rays (%llu casts), "
      "zones %llu/%llu traced, %.3f s\n",
      bake.illumination.width, bake.illumination.height,
      double(texel_density(bake.illumination.texel_size)), (unsigned long long)i.feeler_rays,
      (unsigned long long)i.illumination_rays, (unsigned long long)i.ray_casts,
      (unsigned long long)i.zones_traced, (unsigned long long)i.zones_total, i.seconds);
  std::printf("              caustic power (%.4g, %.4g, %.4g) W of (%.4g, %.4g, %.4g) W sent\n",
              i.power_deposited.x, i.power_deposited.y, i.power_deposited.z, i.power_sent.x,
              i.power_sent.y, i.power_sent.z);
  std::printf(
      "radiosity     %zu patches, %llu shots, %llu light + %llu patch rays "
      "(%llu casts), %.3f s (setup %.3f s)\n",
      r.patch_count, (unsigned long long)r.shots, (unsigned long long)r.light_rays,
      (unsigned long long)r.rays, (unsigned long long)r.ray_casts, r.seconds, r.setup_seconds);
  std::printf("              residual %.3g of emitted (%s), emitted (%.4g, %.4g, %.4g) W\n",
              r.residual_fraction, r.converged ? "converged" : "NOT converged: work cap hit",
              r.power_emitted.x, r.power_emitted.y, r.power_emitted.z);
  std::printf("saved         %s\n", directory.c_str());
}

void run_bake(const BakeOptions& options) {
  const Scene scene = load_or_exit(options.scene_path);
  prepare_output_path(options.output_dir);
  check_bake_destination(options.output_dir, options.force);  // now, not after the bake
  try {
    const ConsoleProgress console(options.quiet);
    const BakeParams params = resolve_params(scene, options);
    const BakeResult bake = bake_scene(scene, params, console.progress());
    SaveBakeOptions save;
    save.params = &params;
    save.force = options.force;
    save_bake(options.output_dir, scene, bake, save);
    print_summary(bake, options.output_dir);
  } catch (const Cancelled&) {
    std::fprintf(stderr, "lightbake: bake cancelled; nothing written\n");
    throw ExitCode{130};
  }
}

}  // namespace

void register_bake(CLI::App& app) {
  auto* cmd = app.add_subcommand("bake", "Bake illumination maps and vertex radiosity");
  auto options = std::make_shared<BakeOptions>();
  BakeParams& p = options->params;
  cmd->add_option("scene", options->scene_path, "Scene file (.toml, .gltf, .glb)")->required();
  cmd->add_option("-o,--output", options->output_dir,
                  "Bake directory to write: new, empty, or a previous bake (replaced; other "
                  "files in it are kept)")
      ->capture_default_str();
  cmd->add_flag("--force", options->force,
                "Also write into a folder that holds no bake (its files are kept)");
  cmd->add_option("--seed", p.seed, "Random seed of both passes")->capture_default_str();
  cmd->add_flag("-q,--quiet", options->quiet, "No progress lines");

  auto* pass1 = "Pass 1: illumination maps";
  cmd->add_option("--feeler-zones", p.illumination.feeler_zones,
                  "Feeler rays on an N x N grid of zones per light")
      ->capture_default_str()
      ->group(pass1)
      ->check(CLI::Range(1, kMaxFeelerGridSide / p.illumination.subzones_side));
  auto* caustic_rays = cmd->add_option("--rays-per-zone-side", p.illumination.rays_per_zone_side,
                                       "Dense rays per traced zone: N x N")
                           ->capture_default_str()
                           ->group(pass1)
                           ->check(CLI::Range(1, kMaxRaysPerZoneSide));
  cmd->add_flag("--origins-over-light", p.illumination.origins_over_light,
                "Start rays all over each light (soft caustics) instead of its centre")
      ->group(pass1);
  cmd->add_flag("!--no-caustic-filter", p.illumination.density_filter,
                "Keep the raw splat: no density-estimation filter of the caustic map")
      ->group(pass1);
  cmd->add_option("--caustic-filter-deposits", p.illumination.filter_deposits,
                  "Density filter: deposits each node's kernel gathers (more = smoother)")
      ->capture_default_str()
      ->group(pass1)
      ->check(CLI::Range(1.0, 1e6));
  cmd->add_option("--caustic-filter-radius", p.illumination.filter_max_radius,
                  "Density filter: largest kernel radius, texels")
      ->capture_default_str()
      ->group(pass1)
      ->check(CLI::Range(1, 64));
  cmd->add_option("--max-depth", p.illumination.max_depth, "Specular bounces per ray")
      ->capture_default_str()
      ->group(pass1)
      ->check(CLI::Range(1, 1000));
  auto* texel_size = cmd->add_option("--texel-size", p.illumination.texel_size,
                                     "Lightmap texel edge, metres (0 = automatic)")
                         ->capture_default_str()
                         ->group(pass1)
                         ->check(CLI::NonNegativeNumber);
  auto* texel_density =
      add_texel_density_option(*cmd, p.illumination)->group(pass1)->excludes(texel_size);

  auto* pass2 = "Pass 2: radiosity";
  const auto counts = CLI::Range(uint64_t{1}, uint64_t{1'000'000'000'000});
  const auto ray_counts = CLI::Range(uint64_t{1}, kMaxRadiosityRayBudget);
  auto* patch_size =
      cmd->add_option(
             "--patch-size", p.radiosity.patch_size,
             "Radiosity patch edge, metres (0 = automatic: ~16 patches along the largest wall)")
          ->capture_default_str()
          ->group(pass2)
          ->check(CLI::NonNegativeNumber);
  auto* ray_budget =
      cmd->add_option("--ray-budget", p.radiosity.ray_budget, "Total radiosity rays (about)")
          ->capture_default_str()
          ->group(pass2)
          ->check(ray_counts);
  cmd->add_option("--min-rays-per-shot", p.radiosity.min_rays_per_shot, "Fewest rays in one shot")
      ->capture_default_str()
      ->group(pass2)
      ->check(counts);
  cmd->add_option("--convergence", p.radiosity.convergence,
                  "Stop when unsent power < this fraction of the emitted power")
      ->capture_default_str()
      ->group(pass2)
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--max-shots", p.radiosity.max_shots,
                  "Hard cap on shots (0 = max(100000, 128 x patches))")
      ->capture_default_str()
      ->group(pass2)
      ->check(CLI::Range(uint64_t{0}, uint64_t{1'000'000'000'000}));
  cmd->add_option("--max-rays", p.radiosity.max_rays,
                  "Hard cap on rays (0 = 4 x budget + what the shot cap needs)")
      ->capture_default_str()
      ->group(pass2);
  cmd->add_option("--max-specular-depth", p.radiosity.max_specular_depth,
                  "Specular bounces per radiosity ray")
      ->capture_default_str()
      ->group(pass2)
      ->check(CLI::NonNegativeNumber);
  cmd->add_flag("--emitters-reflect,!--emitters-lights-only", p.radiosity.emitters_reflect,
                "Diffuse emitters also receive and reflect light")
      ->capture_default_str()
      ->group(pass2);
  auto* soft = "Soft-light texel map";
  cmd->add_option("--soft-gather-rays", p.soft_texels.gather_rays,
                  "Final-gather rays per texel point (0 = resample the vertex radiosity)")
      ->capture_default_str()
      ->group(soft)
      ->check(CLI::Range(0, 4096));
  cmd->add_option("--soft-filter-radius", p.soft_texels.filter_radius,
                  "Half-width in texels of the filter over the gather's correction")
      ->capture_default_str()
      ->group(soft)
      ->check(CLI::Range(0, 16));
  add_threads_option(*cmd);
  add_quality_option(*cmd, options->quality)
      ->excludes(patch_size)
      ->excludes(ray_budget)
      ->excludes(caustic_rays);
  cmd->callback([options, patch_size, ray_budget, caustic_rays, texel_size, texel_density] {
    // A texel size given with --quality wins over the level's (density is not a cost knob
    // alone: it is also what the exported asset needs).
    options->texel_size_given = texel_size->count() > 0 || texel_density->count() > 0;
    options->patch_size_given = patch_size->count() > 0;
    options->ray_budget_given = ray_budget->count() > 0;
    options->caustic_rays_given = caustic_rays->count() > 0;
    run_bake(*options);
  });
}

}  // namespace lb::app
