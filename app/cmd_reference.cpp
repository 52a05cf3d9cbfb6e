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
#include "app/view_options.h"
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
  ViewOptionValues view{.output = "reference.exr",
                        .spp = reference::ReferenceParams{}.spp,
                        .seed = reference::ReferenceParams{}.seed,
                        .max_depth = reference::ReferenceParams{}.max_depth};
  std::string report;  // "" = OUTPUT with .json
  std::string shard;   // "i/n": render one shard of the passes (lightbake merge joins them)
  std::string window;  // "x0,y0,x1,y1": render only these pixels
  reference::ReferenceParams params;  // --time-limit, --light-paths; the rest from `view`
};

void run_reference(ReferenceOptions& options) {
  ViewOptionValues& view = options.view;
  check_view_options(kReference, view);
  reference::ReferenceParams& params = options.params;
  params.width = view.width;
  params.height = view.height;
  params.spp = view.spp;
  params.seed = view.seed;
  params.max_depth = view.max_depth;
  params.terms = view.reference_terms;
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
  if (!options.shard.empty()) {
    const ShardOption shard = parse_shard(options.shard, reference::kMaxReferenceShards);
    params.shard = shard.index;
    params.shard_count = shard.count;
    if (params.time_limit_seconds > 0.0)
      fail(
          "--time-limit: not with --shard (each shard's pass count would depend on its "
          "machine's clock; give --spp)");
    shards::check_shard_extension(view.output, reference::kReferenceShard);
    if (!options.report.empty()) fail("--report: a shard's report is PART.json, beside it");
  }
  try {
    reference::check_reference_params(params);
  } catch (const std::exception& e) {
    fail(e.what());
  }
  if (options.shard.empty() && !is_radiance_image_path(view.output))
    fail(view.output + ": output must be .exr or .png");
  const std::string report_path =
      options.report.empty()
          ? std::filesystem::path(view.output).replace_extension(".json").string()
          : options.report;
  prepare_output_file(view.output, view.force);
  prepare_output_file(report_path, view.force);
  require_free_space(view.output, image_output_bytes(params.width, params.height));

  const Scene scene = load_or_exit(options.scene_path);
  Camera camera;
  try {
    camera = select_camera(scene, view.camera);
  } catch (const std::exception& e) {
    fail(std::string("--camera: ") + e.what());
  }
  const ToneMap tone{view.given("--exposure") ? view.exposure : camera.exposure, view.tone_curve};

  const ConsoleProgress console(view.quiet);  // Ctrl-C cancels: nothing is written
  const Accel accel(scene);
  const reference::ReferenceRenderer renderer(scene, accel, camera, params);
  reference::ReferenceStats stats;
  const reference::Film film = renderer.render(stats, console.progress());

  if (!options.shard.empty()) {
    const nlohmann::json settings = reference::reference_shard_settings(
        scene_hash(scene), camera.name, params, view.tone, tone.exposure);
    reference::write_reference_shard(view.output, options.scene_path, settings, params, film,
                                     stats);
    std::printf("reference  shard %d/%d: %d of %d passes at %dx%d, %.2f s CPU, %.2f s wall\n",
                params.shard, params.shard_count, film.passes(), params.spp, params.width,
                params.height, stats.cpu_seconds, stats.wall_seconds);
    std::printf("wrote      %s, %s\n", view.output.c_str(), report_path.c_str());
    return;
  }
  const std::vector<vec3> pixels = reference::window_in_image(film.average(), params);
  const reference::ReportInfo info{options.scene_path, view.output, camera.name};
  write_radiance_image_and_report(view.output, pixels, params.width, params.height, tone,
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
  std::printf("wrote      %s, %s\n", view.output.c_str(), report_path.c_str());
}

}  // namespace

void register_reference(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "reference", "Unbiased reference render: path tracing + light tracing for caustics");
  auto options = std::make_shared<ReferenceOptions>();
  reference::ReferenceParams& p = options->params;
  cmd->add_option("scene", options->scene_path, "Scene file (.toml, .gltf, .glb)")->required();
  add_view_options(*cmd, kReference, options->view);
  cmd->add_option("--time-limit", p.time_limit_seconds,
                  "Wall seconds after which no new pass starts (0: none)");
  cmd->add_option("--report", options->report, "JSON report path (default: OUTPUT with .json)");
  cmd->add_option("--light-paths", p.light_paths_per_pixel,
                  "Light-tracing paths per pixel per pass (caustics)");
  cmd->add_option("--shard", options->shard,
                  "INDEX/COUNT: render only the passes k with k mod COUNT = INDEX, as .refshard; "
                  "`lightbake merge` joins the COUNT shards into the image, bit for bit "
                  "(docs/farm.md)");
  cmd->add_option("--window", options->window,
                  "x0,y0,x1,y1: render only these pixels (half-open, as compare --region), with "
                  "the bits of the whole render; the image keeps its size, 0 outside");
  cmd->callback([options] {
    try {
      run_reference(*options);
    } catch (const Cancelled&) {
      std::fprintf(stderr, "lightbake: reference cancelled; nothing written\n");
      throw ExitCode{130};
    }
  });
}

}  // namespace lb::app
