// `lightbake snapshot SCENE [BAKE_DIR] -o out.png|out.exr`: one view rendered offscreen with
// OSMesa by the viewer's renderer. Without BAKE_DIR the scene is baked first with the
// default settings. EXR holds linear radiance; PNG is tone mapped (bake/io/image_io.h).

#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include "app/bake_options.h"
#include "app/commands.h"
#include "app/console_progress.h"
#include "app/group_weights_option.h"
#include "app/load.h"
#include "app/output_path.h"
#include "app/view_options.h"
#include "bake/camera.h"
#include "bake/export/gltf_bake_read.h"
#include "bake/export/gltf_export.h"
#include "bake/io/image_io.h"
#include "bake/pipeline/bake.h"
#include "bake/pipeline/bake_io.h"
#include "bake/work_limits.h"
#include "viewer/snapshot.h"

namespace lb::app {

namespace {

struct SnapshotCommand {
  BakeCommandLine bake;  // the settings of the bake made when no BAKE_DIR
  std::string scene_path;
  std::string bake_dir;
  ViewOptionValues view{.frames = SnapshotOptions{}.frames};
  int preset = -1;
  bool no_shadows = false;
  SnapshotOptions options;  // --detail-pixels, --pixel-samples; the rest from `view`
};

void run_snapshot(SnapshotCommand& command) {
  const ViewOptionValues& view = command.view;
  check_view_options(kSnapshot, command.view);
  SnapshotOptions& options = command.options;
  options.width = view.width;
  options.height = view.height;
  options.camera = view.camera;
  options.frames = view.frames;
  options.shadows.samples_per_light = view.shadow_samples;
  options.shadows.resolution = view.shadow_resolution;
  options.shader_directory = view.shaders;
  options.settings.directional = !view.no_directional;  // where the map has a band
  // Colour and depth buffers, the float read-back and the written image: ~48 bytes a pixel.
  require_memory("snapshot: size " + view.size + ", which",
                 double(options.width) * double(options.height) * 48.0);
  const std::string& out = view.output;
  const bool exr = out.size() >= 4 && out.compare(out.size() - 4, 4, ".exr") == 0;
  const bool png = out.size() >= 4 && out.compare(out.size() - 4, 4, ".png") == 0;
  if (!exr && !png) throw std::invalid_argument(out + ": expected a .png or .exr output");
  prepare_output_file(out, view.force);  // fail now, not after a bake
  require_free_space(out, image_output_bytes(options.width, options.height));
  Scene scene = load_or_exit(command.scene_path);
  const std::vector<float> group_weights = scene_group_weights(scene, view.group_weights);
  // A bad camera name fails before any bake; without --exposure the camera's own applies.
  const Camera camera = select_camera(scene, options.camera);
  options.settings.tone.exposure = view.given("--exposure") ? view.exposure : camera.exposure;
  if (command.preset >= 0) options.settings = figure8_preset(command.preset, options.settings);
  options.settings.term = view.term;
  options.settings.tone.curve = view.tone_curve;
  if (command.no_shadows) options.settings.shadows = false;
  options.settings.direct_mode = view.direct_mode;

  std::optional<BakeResult> bake;
  if (!command.bake_dir.empty()) {
    bake = load_bake(command.bake_dir, scene);
  } else if (!view.no_bake && is_lightbake_gltf(command.scene_path)) {
    bake = read_gltf_bake(command.scene_path, scene);  // the light `lightbake export` wrote
  } else if (!view.no_bake) {
    if (view.directional || view.no_directional) command.bake.directional = view.directional;
    const BakeParams params = resolve_bake_params(scene, command.bake);
    std::fprintf(stderr, "lightbake: no bake directory given, baking at quality %s\n",
                 to_string(params.quality));
    try {
      const ConsoleProgress console(view.quiet);
      bake = bake_scene(scene, params, console.progress());
    } catch (const Cancelled&) {
      std::fprintf(stderr, "lightbake: snapshot cancelled; nothing written\n");
      throw ExitCode{130};
    }
  }
  apply_group_weights(group_weights, scene, bake ? &*bake : nullptr);
  ShadowResolution shadows;
  const Image radiance = render_snapshot(scene, bake ? &*bake : nullptr, options, &shadows);
  if (!view.quiet && !shadows.caster.empty()) {
    std::printf("shadows %d texels a face for '%s', %.1f mm thick %.2f m from a light%s\n",
                shadows.resolution, shadows.caster.c_str(), 1000.0 * shadows.thickness,
                double(shadows.distance), shadows.capped ? " (held by the memory budget)" : "");
  }
  if (exr) {
    write_exr(out, radiance, ExrPixelType::float32);
  } else {
    write_png_tonemapped(out, radiance, options.settings.tone);
  }
  std::printf("wrote %s (%dx%d, term %s)\n", out.c_str(), options.width, options.height,
              to_string(options.settings.term));
}

}  // namespace

void register_snapshot(CLI::App& app) {
  auto* cmd = app.add_subcommand("snapshot", "Render one view offscreen (OSMesa) to PNG or EXR");
  auto command = std::make_shared<SnapshotCommand>();
  // A still image: 2 x 2 sub-pixel samples took the Cornell box's raster error from 5.7% to
  // 4.7% per diffuse pixel against the reference (bench/results/LOG.md) for 4 frames.
  command->options.pixel_samples = 2;
  cmd->add_option("scene", command->scene_path, "Scene file (.toml, .gltf, .glb)")->required();
  cmd->add_option("bake_dir", command->bake_dir, "Bake directory (default: bake first)");
  add_view_options(*cmd, kSnapshot, command->view);
  cmd->add_option("--preset", command->preset,
                  "Figure 8 lighting: 0 direct, 1 +ambient, 2 +radiosity, 3 +caustics")
      ->check(CLI::Range(0, kFigure8PresetCount - 1));
  cmd->add_option("--detail-pixels", command->options.settings.detail_pixels,
                  "Levels of detail: draw far meshes coarser, up to this many pixels of "
                  "geometric error (0: full detail)")
      ->check(CLI::Range(0.0f, 64.0f))
      ->capture_default_str();
  add_bake_options(*cmd, command->bake, kBakeFirstGroup, /*with_seed=*/true);
  cmd->add_flag("--no-shadows", command->no_shadows, "Unoccluded direct light");
  cmd->add_option("--pixel-samples", command->options.pixel_samples,
                  "N: each pixel averages N x N sub-pixel samples (a box filter, as the "
                  "reference integrates a pixel), each with its own shadow points; 1: the pixel's "
                  "centre (always with --direct stochastic)")
      ->check(CLI::Range(1, 16))
      ->capture_default_str();
  cmd->callback([command] { run_snapshot(*command); });
}

}  // namespace lb::app
