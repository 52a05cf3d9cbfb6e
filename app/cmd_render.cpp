// `lightbake render SCENE [BAKE_DIR] --spp N --size WxH --camera NAME|INDEX -o out.exr|out.png`:
// the high-quality distributed ray tracer over a bake (loaded, or made first when no BAKE_DIR
// is given). Prints the paper's Table 1 and writes OUT.json beside the image.

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "app/bake_options.h"
#include "app/cli_parse.h"
#include "app/commands.h"
#include "app/console_progress.h"
#include "app/group_weights_option.h"
#include "app/load.h"
#include "app/output_path.h"
#include "app/radiance_output.h"
#include "app/thread_option.h"
#include "bake/camera.h"
#include "bake/hq/hq_render.h"
#include "bake/hq/ray_report.h"
#include "bake/io/atomic_file.h"
#include "bake/export/gltf_bake_read.h"
#include "bake/export/gltf_export.h"
#include "bake/io/image_io.h"
#include "bake/json_text.h"
#include "bake/pipeline/bake.h"
#include "bake/pipeline/bake_io.h"

namespace lb::app {

namespace {

struct RenderOptions {
  std::string scene_path;
  std::string bake_dir;
  std::string output = "render.exr";
  std::string size = "1024x768";
  std::string camera;  // "" = the scene's first camera
  int spp = 16;
  int passes = 1;
  float exposure = 0.0f;
  bool exposure_given = false;  // else the camera's own exposure
  std::string tone = "aces";
  uint64_t seed = 1;
  bool seed_given = false;  // it seeds the bake made when no BAKE_DIR too
  BakeCommandLine bake;     // that bake's settings
  int max_depth = 16;
  int final_gather = 0;
  bool final_gather_given = false;  // else automatic (kAutoGatherSpp)
  bool quiet = false;
  bool force = false;
  std::string terms = "direct,map,radiosity";
  std::string shard;  // "i/n": render one shard of the tiles (lightbake merge joins them)
  std::string group_weights;
};

// From this many samples per pixel the final gather (1 ray a sample) wins per pixel as well as
// in bias against the reference; below, its noise costs more than interpolation's bias
// (bench/results/LOG.md, "the final gather": Cornell box MRE 0.032 vs 0.040 at 256 spp, 0.055
// vs 0.041 at 64).
constexpr int kAutoGatherSpp = 256;

void run_render(const RenderOptions& options) {
  HqParams params;
  parse_size(options.size, params.width, params.height);
  params.samples_per_side = parse_samples_per_side(options.spp);
  params.seed = options.seed;
  params.max_depth = options.max_depth;
  const bool gather_by_default = options.spp * options.passes >= kAutoGatherSpp;
  params.final_gather = options.final_gather_given ? options.final_gather : gather_by_default;
  if (!is_radiance_image_path(options.output))
    fail(options.output + ": output must be .exr or .png");
  if (!options.shard.empty()) {
    const ShardOption shard = parse_shard(options.shard, kMaxShards);
    params.shard = shard.index;
    params.shard_count = shard.count;
    if (lowercase_extension(options.output) != ".exr")
      fail(options.output + ": a shard is written as .exr (lightbake merge makes the .png)");
  }
  const std::string report_path =
      std::filesystem::path(options.output).replace_extension(".json").string();
  prepare_output_file(options.output, options.force);
  prepare_output_file(report_path, options.force);
  require_free_space(options.output, image_output_bytes(params.width, params.height));
  ToneMap tone;
  tone.exposure = options.exposure;
  try {
    tone.curve = parse_tone_curve(options.tone);
  } catch (const std::exception&) {
    fail("--tone: expected clamp, reinhard or aces, got '" + options.tone + "'");
  }
  if (options.passes < 1) fail("--passes: must be at least 1");
  check_hq_params(params);  // before any bake: an absurd size or spp fails in a second
  params.direct = options.terms.find("direct") != std::string::npos;
  params.illumination_map = options.terms.find("map") != std::string::npos;
  params.radiosity = options.terms.find("radiosity") != std::string::npos;

  Scene scene = load_or_exit(options.scene_path);
  const std::vector<float> group_weights = scene_group_weights(scene, options.group_weights);
  const Camera camera = select_camera(scene, options.camera);
  if (!options.exposure_given) tone.exposure = camera.exposure;

  const ConsoleProgress console(options.quiet);  // Ctrl-C cancels: nothing is written
  const Progress& progress = console.progress();

  const auto bake_start = std::chrono::steady_clock::now();
  BakeResult bake;
  if (options.bake_dir.empty() && is_lightbake_gltf(options.scene_path)) {
    bake = read_gltf_bake(options.scene_path, scene);  // the light `lightbake export` wrote
  } else if (options.bake_dir.empty()) {
    const BakeParams bake_params = resolve_bake_params(
        scene, options.bake, options.seed_given ? std::optional(options.seed) : std::nullopt);
    bake = bake_scene(scene, bake_params, progress);
  } else {
    bake = load_bake(options.bake_dir, scene);
  }
  apply_group_weights(group_weights, scene, &bake);
  // An export made with `--contents all` carries the direct light in its map already.
  if (bake.illumination.holds_direct_light) params.direct = false;
  const double bake_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - bake_start).count();
  const BakedScene baked = make_baked_scene(scene, bake);

  const HqRenderer renderer(baked, params);
  HqStats stats;
  const std::vector<vec3> pixels = renderer.render(camera, options.passes, stats, progress);

  const RayTable table = make_ray_table(stats.rays, &bake);
  RenderReportInfo info;
  info.scene_path = options.scene_path;
  info.bake_dir = options.bake_dir;
  info.output_path = options.output;
  info.camera = camera.name;
  info.params = params;
  info.passes = options.passes;
  info.bake_seconds = bake_seconds;
  nlohmann::json report = nlohmann::json::parse(render_report_json(info, stats, table));
  // What `lightbake merge` checks shards against each other by, and the PNG settings it uses.
  report["terms"] = options.terms;
  report["scene_hash"] = scene_hash(scene);
  report["bake_hash"] = bake_hash(bake);
  report["tone"] = {{"curve", options.tone}, {"exposure", tone.exposure}};
  if (!options.shard.empty())
    report["shard"] = {
        {"index", params.shard}, {"count", params.shard_count}, {"tile_size", params.tile_size}};
  write_radiance_image_and_report(options.output, pixels, params.width, params.height, tone,
                                  report_path, std::move(report));

  double render_seconds = 0.0;
  for (double s : stats.pass_seconds) render_seconds += s;
  std::printf("%s", format_ray_table(table, "render").c_str());
  std::printf("render     %dx%d, %d spp, %.2f s (%.2f Mrays/s), bake %.2f s\n", params.width,
              params.height, options.spp * options.passes, render_seconds,
              render_seconds > 0 ? 1e-6 *
                                       double(stats.rays.viewing + stats.rays.shadow +
                                              stats.rays.gather + stats.rays.gather_shadow) /
                                       render_seconds
                                 : 0.0,
              bake_seconds);
  std::printf("wrote      %s, %s\n", options.output.c_str(), report_path.c_str());
}

}  // namespace

void register_render(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "render", "High-quality render: distributed ray tracing with one shadow ray per viewing ray");
  auto options = std::make_shared<RenderOptions>();
  cmd->add_option("scene", options->scene_path, "Scene file (.toml, .gltf, .glb)")->required();
  cmd->add_option("bake_dir", options->bake_dir, "Bake directory (omitted: bake first)");
  cmd->add_option("-o,--output", options->output, "Image to write (.exr linear, .png tone mapped)");
  cmd->add_option("--spp", options->spp, "Samples per pixel per pass, a square (16 = 4x4)");
  cmd->add_option("--passes", options->passes, "Passes of --spp samples, accumulated");
  cmd->add_option("--size", options->size, "Image size WIDTHxHEIGHT");
  cmd->add_option("--camera", options->camera,
                  "Camera name or index, or 'fit' (default: the scene's first)");
  auto* exposure = cmd->add_option("--exposure", options->exposure,
                                   "PNG exposure, stops (default: the camera's)");
  cmd->add_option("--tone", options->tone, "PNG tone curve: clamp, reinhard, aces");
  auto* seed = cmd->add_option("--seed", options->seed, "Random seed (bake and render)");
  cmd->add_option("--max-depth", options->max_depth, "Specular bounces per viewing path");
  cmd->add_option("--terms", options->terms,
                  "Debug: the diffuse terms to sum, any of direct,map,radiosity");
  auto* final_gather =
      cmd->add_option("--final-gather", options->final_gather,
                      "Soft light gathered from the bake with N rays per diffuse hit, instead of "
                      "interpolated vertex radiosity (0: off; the flag alone: 1; default: 1 from " +
                          std::to_string(kAutoGatherSpp) + " samples per pixel, else 0)")
          ->expected(0, 1)
          ->default_str("1");
  cmd->add_flag("-q,--quiet", options->quiet, "No progress output");
  cmd->add_flag("--force", options->force,
                "Replace the image or its .json report even if lightbake did not write them");
  cmd->add_option("--shard", options->shard,
                  "INDEX/COUNT: render only this shard's tiles, as .exr; `lightbake merge` joins "
                  "the COUNT shards into the whole image, bit for bit (docs/farm.md)");
  add_bake_options(*cmd, options->bake, kBakeFirstGroup, /*with_seed=*/false);
  add_group_weights_option(*cmd, options->group_weights);
  add_threads_option(*cmd);
  cmd->callback([options, exposure, final_gather, seed] {
    options->exposure_given = exposure->count() > 0;
    options->seed_given = seed->count() > 0;
    options->final_gather_given = final_gather->count() > 0;
    try {
      run_render(*options);
    } catch (const Cancelled&) {
      std::fprintf(stderr, "lightbake: render cancelled; nothing written\n");
      throw ExitCode{130};
    }
  });
}

}  // namespace lb::app
