// `lightbake render SCENE [BAKE_DIR] --spp N --size WxH --camera NAME|INDEX -o out.exr|out.png`:
// the high-quality distributed ray tracer over a bake (loaded, or made first when no BAKE_DIR
// is given). Prints the paper's Table 1 and writes OUT.json beside the image; with --shard i/n,
// its tiles to PART.rendershard (bake/hq/render_shards.h).

#include <chrono>
#include <cmath>
#include <cstdio>
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
#include "app/view_options.h"
#include "bake/camera.h"
#include "bake/hq/hq_render.h"
#include "bake/hq/ray_report.h"
#include "bake/hq/render_shards.h"
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
  // --seed seeds the bake made when no BAKE_DIR too; not given, --final-gather is automatic
  // (kAutoGatherSpp) and the camera's exposure applies.
  ViewOptionValues view{
      .output = "render.exr", .size = "1024x768", .terms = "direct,map,radiosity"};
  BakeCommandLine bake;  // the settings of the bake made when no BAKE_DIR
  std::string shard;  // "i/n": render one shard of the tiles (lightbake merge joins them)
};

void run_render(RenderOptions& options) {
  ViewOptionValues& view = options.view;
  check_view_options(kRender, view);
  HqParams params;
  params.width = view.width;
  params.height = view.height;
  params.samples_per_side = view.samples_per_side;
  params.seed = view.seed;
  params.max_depth = view.max_depth;
  const bool gather_by_default = view.spp * view.passes >= kAutoGatherSpp;
  params.final_gather = view.given("--final-gather") ? view.final_gather : gather_by_default;
  params.direct = view.render_direct;
  params.illumination_map = view.render_map;
  params.radiosity = view.render_radiosity;
  const bool sharded = !options.shard.empty();
  if (sharded) {
    const ShardOption shard = parse_shard(options.shard, kMaxShards);
    params.shard = shard.index;
    params.shard_count = shard.count;
    shards::check_shard_extension(view.output, kRenderShard);
  } else if (!is_radiance_image_path(view.output)) {
    fail(view.output + ": output must be .exr or .png");
  }
  const std::string report_path = shards::shard_report_path(view.output);
  prepare_output_file(view.output, view.force);
  prepare_output_file(report_path, view.force);
  require_free_space(view.output, image_output_bytes(params.width, params.height));
  check_hq_params(params);  // before any bake: an absurd size or spp fails in a second

  Scene scene = load_or_exit(options.scene_path);
  const std::vector<float> group_weights = scene_group_weights(scene, view.group_weights);
  const Camera camera = select_camera(scene, view.camera);
  const ToneMap tone{view.given("--exposure") ? view.exposure : camera.exposure, view.tone_curve};

  const ConsoleProgress console(view.quiet);  // Ctrl-C cancels: nothing is written
  const Progress& progress = console.progress();

  const auto bake_start = std::chrono::steady_clock::now();
  BakeResult bake;
  if (options.bake_dir.empty() && is_lightbake_gltf(options.scene_path)) {
    bake = read_gltf_bake(options.scene_path, scene);  // the light `lightbake export` wrote
  } else if (options.bake_dir.empty()) {
    if (view.directional || view.no_directional) options.bake.directional = view.directional;
    const BakeParams bake_params = resolve_bake_params(
        scene, options.bake, view.given("--seed") ? std::optional(view.seed) : std::nullopt);
    bake = bake_scene(scene, bake_params, progress);
  } else {
    bake = load_bake(options.bake_dir, scene);
  }
  apply_group_weights(group_weights, scene, &bake);
  // An export made with `--contents all` carries the direct light in its map already.
  if (bake.illumination.holds_direct_light) params.direct = false;
  const double bake_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - bake_start).count();
  BakedScene baked = make_baked_scene(scene, bake);
  baked.directional = baked.directional && !view.no_directional;

  const HqRenderer renderer(baked, params);
  HqStats stats;
  const std::vector<vec3> pixels = renderer.render(camera, view.passes, stats, progress);

  const RayTable table = make_ray_table(stats.rays, &bake);
  RenderReportInfo info;
  info.scene_path = options.scene_path;
  info.bake_dir = options.bake_dir;
  info.output_path = view.output;
  info.camera = camera.name;
  info.params = params;
  info.passes = view.passes;
  info.bake_seconds = bake_seconds;
  nlohmann::json report = nlohmann::json::parse(render_report_json(info, stats, table));
  // What `lightbake merge` checks shards against each other by, and the PNG settings it uses.
  report["terms"] = view.terms;
  report["scene_hash"] = scene_hash(scene);
  report["bake_hash"] = bake_hash(bake);
  report["tone"] = {{"curve", view.tone}, {"exposure", tone.exposure}};
  if (sharded)
    write_render_shard(view.output, options.scene_path, options.bake_dir,
                       render_shard_settings(report, params.tile_size), params.shard,
                       params.shard_count, pixels, report);
  else
    write_radiance_image_and_report(view.output, pixels, params.width, params.height, tone,
                                    report_path, std::move(report));

  double render_seconds = 0.0;
  for (double s : stats.pass_seconds) render_seconds += s;
  std::printf("%s", format_ray_table(table, "render").c_str());
  std::printf("render     %dx%d, %d spp, %.2f s (%.2f Mrays/s), bake %.2f s\n", params.width,
              params.height, view.spp * view.passes, render_seconds,
              render_seconds > 0 ? 1e-6 *
                                       double(stats.rays.viewing + stats.rays.shadow +
                                              stats.rays.gather + stats.rays.gather_shadow) /
                                       render_seconds
                                 : 0.0,
              bake_seconds);
  std::printf("wrote      %s, %s\n", view.output.c_str(), report_path.c_str());
}

}  // namespace

void register_render(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "render", "High-quality render: distributed ray tracing with one shadow ray per viewing ray");
  auto options = std::make_shared<RenderOptions>();
  cmd->add_option("scene", options->scene_path, "Scene file (.toml, .gltf, .glb)")->required();
  cmd->add_option("bake_dir", options->bake_dir, "Bake directory (omitted: bake first)");
  add_view_options(*cmd, kRender, options->view);
  cmd->add_option("--shard", options->shard,
                  "INDEX/COUNT: render only this shard's tiles, to -o PART.rendershard; `lightbake "
                  "merge` joins the COUNT shards into the whole image, bit for bit (docs/farm.md)");
  add_bake_options(*cmd, options->bake, kBakeFirstGroup, /*with_seed=*/false);
  cmd->callback([options] {
    try {
      run_render(*options);
    } catch (const Cancelled&) {
      std::fprintf(stderr, "lightbake: render cancelled; nothing written\n");
      throw ExitCode{130};
    }
  });
}

}  // namespace lb::app
