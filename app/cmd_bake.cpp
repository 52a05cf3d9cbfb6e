// `lightbake bake SCENE -o DIR`: run both bake passes and save them as a bake directory
// (bake/pipeline/bake_io.h). The options are the table of bake settings (app/bake_options.h);
// Ctrl-C cancels cleanly (nothing is written), as does any error. A folder that is not a previous
// bake is refused before baking.

#include <cstdio>
#include <string>

#include "app/bake_options.h"
#include "app/cli_parse.h"
#include "app/commands.h"
#include "app/console_progress.h"
#include "app/deprecated_option.h"
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
  BakeCommandLine settings;
  std::string old_max_depth;  // --max-depth, the old spelling of --caustic-max-depth
  bool force = false;
  bool quiet = false;
};

double old_spelling_number(const char* name, const std::string& text) {
  try {
    size_t used = 0;
    const double value = std::stod(text, &used);
    if (used == text.size()) return value;
  } catch (const std::exception&) {
  }
  throw std::invalid_argument(std::string(name) + " '" + text + "': expected a number");
}

void print_summary(const Scene& scene, const BakeResult& bake, const std::string& directory) {
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
  std::printf("memory        %s at most, for %zu triangles and %d x %d texels\n",
              format_bytes(double(peak_resident_bytes())).c_str(), triangle_count(scene),
              bake.illumination.width, bake.illumination.height);
  std::printf("saved         %s\n", directory.c_str());
}

void run_bake(const BakeOptions& options) {
  const Scene scene = load_or_exit(options.scene_path);
  prepare_output_path(options.output_dir);
  check_bake_destination(options.output_dir, options.force);  // now, not after the bake
  try {
    const ConsoleProgress console(options.quiet);
    BakeSettingsRequest request = options.settings.request();
    if (!options.old_max_depth.empty())
      request.given.push_back({find_bake_setting("caustic_max_depth"),
                               old_spelling_number("--max-depth", options.old_max_depth)});
    const BakeParams params = resolve_bake_params(scene, request);
    const BakeResult bake = bake_scene(scene, params, console.progress());
    SaveBakeOptions save;
    save.params = &params;
    save.force = options.force;
    save_bake(options.output_dir, scene, bake, save);
    print_summary(scene, bake, options.output_dir);
  } catch (const Cancelled&) {
    std::fprintf(stderr, "lightbake: bake cancelled; nothing written\n");
    throw ExitCode{130};
  }
}

}  // namespace

void register_bake(CLI::App& app) {
  auto* cmd = app.add_subcommand("bake", "Bake illumination maps and vertex radiosity");
  auto options = std::make_shared<BakeOptions>();
  cmd->add_option("scene", options->scene_path, "Scene file (.toml, .gltf, .glb)")->required();
  cmd->add_option("-o,--output", options->output_dir,
                  "Bake directory to write: new, empty, or a previous bake (replaced; other "
                  "files in it are kept)")
      ->capture_default_str();
  cmd->add_flag("--force", options->force,
                "Also write into a folder that holds no bake (its files are kept)");
  cmd->add_flag("-q,--quiet", options->quiet, "No progress lines");
  add_bake_options(*cmd, options->settings, nullptr, /*with_seed=*/true);
  for (const auto& [setting, option] : options->settings.options)
    if (std::string_view(setting->key) == "caustic_max_depth")
      add_deprecated_alias(*cmd, option, "--max-depth", options->old_max_depth);
  add_threads_option(*cmd);
  cmd->callback([options] { run_bake(*options); });
}

}  // namespace lb::app
