// `lightbake bake SCENE -o DIR`: run both bake passes and save them as a bake directory
// (bake/pipeline/bake_io.h). The options are the table of bake settings (app/bake_options.h);
// Ctrl-C cancels cleanly (nothing is written), as does any error. A folder that is not a previous
// bake is refused before baking. `--shard i/n -o PART.pass1` traces only shard i of pass 1's
// dense rays and writes its sums (bake/pipeline/pass1_shard_io.h); `lightbake merge` joins the
// n shards into the bake, bit for bit (docs/farm.md).

#include <chrono>
#include <cstdio>
#include <string>

#include "app/bake_options.h"
#include "app/bake_summary.h"
#include "app/cli_parse.h"
#include "app/commands.h"
#include "app/console_progress.h"
#include "app/load.h"
#include "app/output_path.h"
#include "app/radiance_output.h"
#include "app/thread_option.h"
#include "bake/pipeline/bake.h"
#include "bake/pipeline/bake_io.h"
#include "bake/pipeline/pass1_shard_io.h"

namespace lb::app {

namespace {

struct BakeOptions {
  std::string scene_path;
  std::string output_dir = "bake";
  BakeCommandLine settings;
  bool force = false;
  bool quiet = false;
  std::string shard;  // "i/n": trace only this shard of pass 1 (lightbake merge joins them)
};

// Pass-1 shards share at most this many (each holds the plan; more would be tasks of a few rays).
constexpr int kMaxBakeShards = 4096;

void run_bake_shard(const BakeOptions& options) {
  const ShardOption shard = parse_shard(options.shard, kMaxBakeShards);
  const std::string& data_path = options.output_dir;
  shards::check_shard_extension(data_path, kPass1Shard);
  const std::string report_path = shards::shard_report_path(data_path);
  prepare_output_file(data_path, options.force);
  prepare_output_file(report_path, options.force);
  const Scene scene = load_or_exit(options.scene_path);
  try {
    const auto start = std::chrono::steady_clock::now();
    const ConsoleProgress console(options.quiet);
    const BakeParams params = resolve_bake_params(scene, options.settings);
    const Pass1Shard part =
        bake_pass1_shard(scene, params, shard.index, shard.count, console.progress());
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    write_pass1_shard(data_path, scene, params, shard.index, shard.count, part, seconds);
    std::printf("pass 1 shard %d/%d: %llu dense rays (%llu casts) into a %dx%d atlas, %.3f s\n",
                shard.index, shard.count, (unsigned long long)part.sums.tally.rays,
                (unsigned long long)part.sums.tally.casts, part.atlas_width, part.atlas_height,
                seconds);
    std::printf("wrote         %s, %s\n", data_path.c_str(), report_path.c_str());
  } catch (const Cancelled&) {
    std::fprintf(stderr, "lightbake: bake cancelled; nothing written\n");
    throw ExitCode{130};
  }
}

void run_bake(const BakeOptions& options) {
  if (!options.shard.empty()) return run_bake_shard(options);
  const Scene scene = load_or_exit(options.scene_path);
  prepare_output_path(options.output_dir);
  check_bake_destination(options.output_dir, options.force);  // now, not after the bake
  try {
    const ConsoleProgress console(options.quiet);
    const BakeParams params = resolve_bake_params(scene, options.settings);
    BakeCallbacks callbacks;
    callbacks.on_atlas = [&](int width, int height) {
      require_free_space(options.output_dir, bake_files_bytes(scene, width, height,
                                                              params.illumination.directional));
    };
    const BakeResult bake = bake_scene(scene, params, console.progress(), callbacks);
    SaveBakeOptions save;
    save.params = &params;
    save.force = options.force;
    save_bake(options.output_dir, scene, bake, save);
    print_bake_summary(scene, bake, options.output_dir);
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
  cmd->add_option("--shard", options->shard,
                  "INDEX/COUNT: trace only this shard of pass 1's rays and write its sums to "
                  "-o PART.pass1; `lightbake merge` joins the COUNT shards into the bake, bit "
                  "for bit (docs/farm.md)");
  add_bake_options(*cmd, options->settings, nullptr, /*with_seed=*/true);
  add_threads_option(*cmd);
  cmd->callback([options] { run_bake(*options); });
}

}  // namespace lb::app
