// `lightbake reference SCENE --spp N --size WxH -o out.exr [--time-limit S] [--seed S]
// [--camera NAME|INDEX] [--report r.json] [--terms all|direct]`: the unbiased reference
// renderer (bake/reference/), no bake needed. Writes linear radiance (.exr) or the render
// command's tone mapping (.png), and a JSON report (OUT.json unless --report says otherwise).
// With `--shard i/n -o PART.refshard` it renders one shard of the passes and writes their exact
// sums (bake/reference/reference_shard.h); `lightbake merge` makes the image.
// `--window x0,y0,x1,y1` renders only those pixels (half-open, as `compare --region`), with the
// bits they have in the whole render; the image is still the whole size, 0 outside the window.

#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "app/cli_parse.h"
#include "app/commands.h"
#include "app/console_progress.h"
#include "app/load.h"
#include "app/output_path.h"
#include "app/radiance_output.h"
#include "app/thread_option.h"
#include "bake/camera.h"
#include "bake/io/atomic_file.h"
#include "bake/io/image_io.h"
#include "bake/metrics/image_metrics.h"
#include "bake/pipeline/bake_io.h"
#include "bake/reference/reference.h"
#include "bake/reference/reference_shard.h"
#include "bake/reference/report.h"

namespace lb::app {

namespace {

struct ReferenceOptions {
  std::string scene_path;
  std::string output = "reference.exr";
  std::string report;  // "" = OUTPUT with .json
  std::string size = "640x480";
  std::string camera;
  std::string terms = "all";
  std::string tone = "aces";
  float exposure = 0.0f;
  bool exposure_given = false;
  bool quiet = false;
  bool force = false;
  std::string shard;   // "i/n": render one shard of the passes (lightbake merge joins them)
  std::string window;  // "x0,y0,x1,y1": render only these pixels
  reference::ReferenceParams params;
};

void run_reference(ReferenceOptions& options) {
  reference::ReferenceParams& params = options.params;
  try {
    parse_size(options.size, params.width, params.height);
  } catch (const std::exception& e) {
    fail(std::string("--size: ") + e.what());
  }
  if (!options.window.empty()) {
    PixelRegion r;
    try {
      r = parse_region(options.window);
    } catch (const std::exception&) {
      fail("--window '" + options.window +
           "': expected x0,y0,x1,y1 in pixels with x0 < x1, y0 < y1");
    }
    if (r.x0 < 0 || r.y0 < 0 || r.x1 > params.width || r.y1 > params.height)
      fail("--window '" + options.window + "': outside the " + std::to_string(params.width) + "x" +
           std::to_string(params.height) + " image");
    params.window = {r.x0, r.y0, r.x1 - r.x0, r.y1 - r.y0};
  }
  if (options.terms == "all")
    params.terms = reference::Terms::all;
  else if (options.terms == "direct")
    params.terms = reference::Terms::direct;
  else
    fail("--terms: expected all or direct, got '" + options.terms + "'");
  if (!options.shard.empty()) {
    const ShardOption shard = parse_shard(options.shard, reference::kMaxReferenceShards);
    params.shard = shard.index;
    params.shard_count = shard.count;
    if (params.time_limit_seconds > 0.0)
      fail(
          "--time-limit: not with --shard (each shard's pass count would depend on its "
          "machine's clock; give --spp)");
    shards::check_shard_extension(options.output, reference::kReferenceShard);
    if (!options.report.empty()) fail("--report: a shard's report is PART.json, beside it");
  }
  try {
    reference::check_reference_params(params);
  } catch (const std::exception& e) {
    fail(e.what());
  }
  if (options.shard.empty() && !is_radiance_image_path(options.output))
    fail(options.output + ": output must be .exr or .png");
  ToneMap tone;
  try {
    tone.curve = parse_tone_curve(options.tone);
  } catch (const std::exception&) {
    fail("--tone: expected clamp, reinhard or aces, got '" + options.tone + "'");
  }
  const std::string report_path =
      options.report.empty()
          ? std::filesystem::path(options.output).replace_extension(".json").string()
          : options.report;
  prepare_output_file(options.output, options.force);
  prepare_output_file(report_path, options.force);
  require_free_space(options.output, image_output_bytes(params.width, params.height));

  const Scene scene = load_or_exit(options.scene_path);
  Camera camera;
  try {
    camera = select_camera(scene, options.camera);
  } catch (const std::exception& e) {
    fail(std::string("--camera: ") + e.what());
  }
  tone.exposure = options.exposure_given ? options.exposure : camera.exposure;

  const ConsoleProgress console(options.quiet);  // Ctrl-C cancels: nothing is written
  const Accel accel(scene);
  const reference::ReferenceRenderer renderer(scene, accel, camera, params);
  reference::ReferenceStats stats;
  const reference::Film film = renderer.render(stats, console.progress());

  if (!options.shard.empty()) {
    const nlohmann::json settings = reference::reference_shard_settings(
        scene_hash(scene), camera.name, params, options.tone, tone.exposure);
    reference::write_reference_shard(options.output, options.scene_path, settings, params, film,
                                     stats);
    std::printf("reference  shard %d/%d: %d of %d passes at %dx%d, %.2f s CPU, %.2f s wall\n",
                params.shard, params.shard_count, film.passes(), params.spp, params.width,
                params.height, stats.cpu_seconds, stats.wall_seconds);
    std::printf("wrote      %s, %s\n", options.output.c_str(), report_path.c_str());
    return;
  }
  const std::vector<vec3> pixels = reference::window_in_image(film.average(), params);
  const reference::ReportInfo info{options.scene_path, options.output, camera.name};
  write_radiance_image_and_report(options.output, pixels, params.width, params.height, tone,
                                  report_path,
                                  nlohmann::json::parse(reference::report_json(info, params, film,
                                                                               stats)));

  const reference::NoiseEstimate noise = film.noise();
  if (!params.window.empty())
    std::printf(
        "window     %d,%d,%d,%d: %dx%d of the %dx%d image (0 outside; noise below is the "
        "window's)\n",
        params.window.x, params.window.y, params.window.x + params.window.width,
        params.window.y + params.window.height, params.window.width, params.window.height,
        params.width, params.height);
  std::printf("reference  %dx%d, %d spp, %.2f s CPU, %.2f s wall, %.2f Mrays/CPU s\n", params.width,
              params.height, film.passes(), stats.cpu_seconds, stats.wall_seconds,
              stats.cpu_seconds > 0 ? 1e-6 * double(stats.rays.total()) / stats.cpu_seconds : 0.0);
  std::printf("noise      %.2f%% per pixel (RMS), %.3f%% on the image mean\n",
              100.0 * noise.pixel_relative_standard_error,
              100.0 * noise.mean_relative_standard_error);
  std::printf("wrote      %s, %s\n", options.output.c_str(), report_path.c_str());
}

}  // namespace

void register_reference(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "reference", "Unbiased reference render: path tracing + light tracing for caustics");
  auto options = std::make_shared<ReferenceOptions>();
  reference::ReferenceParams& p = options->params;
  cmd->add_option("scene", options->scene_path, "Scene file (.toml, .gltf, .glb)")->required();
  cmd->add_option("-o,--output", options->output, "Image to write (.exr linear, .png tone mapped)");
  cmd->add_option("--spp", p.spp, "Samples (eye paths) per pixel, one per pass");
  cmd->add_option("--size", options->size, "Image size WIDTHxHEIGHT");
  cmd->add_option("--time-limit", p.time_limit_seconds,
                  "Wall seconds after which no new pass starts (0: none)");
  cmd->add_option("--seed", p.seed, "Random seed");
  cmd->add_option("--camera", options->camera,
                  "Camera name or index, or 'fit' (default: the scene's first)");
  cmd->add_option("--report", options->report, "JSON report path (default: OUTPUT with .json)");
  cmd->add_option("--terms", options->terms,
                  "all, or direct: only light reaching the first diffuse surface from a light");
  cmd->add_option("--max-depth", p.max_depth,
                  "Scattering vertices before a path is dropped (guard)");
  cmd->add_option("--light-paths", p.light_paths_per_pixel,
                  "Light-tracing paths per pixel per pass (caustics)");
  auto* exposure = cmd->add_option("--exposure", options->exposure,
                                   "PNG exposure, stops (default: the camera's)");
  cmd->add_option("--tone", options->tone, "PNG tone curve: clamp, reinhard, aces");
  cmd->add_flag("-q,--quiet", options->quiet, "No progress output");
  cmd->add_flag("--force", options->force,
                "Replace the image or its report even if lightbake did not write them");
  cmd->add_option("--shard", options->shard,
                  "INDEX/COUNT: render only the passes k with k mod COUNT = INDEX, as .refshard; "
                  "`lightbake merge` joins the COUNT shards into the image, bit for bit "
                  "(docs/farm.md)");
  cmd->add_option("--window", options->window,
                  "x0,y0,x1,y1: render only these pixels (half-open, as compare --region), with "
                  "the bits of the whole render; the image keeps its size, 0 outside");
  add_threads_option(*cmd);
  cmd->callback([options, exposure] {
    options->exposure_given = exposure->count() > 0;
    try {
      run_reference(*options);
    } catch (const Cancelled&) {
      std::fprintf(stderr, "lightbake: reference cancelled; nothing written\n");
      throw ExitCode{130};
    }
  });
}

}  // namespace lb::app
