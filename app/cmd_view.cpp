// `lightbake view SCENE [BAKE_DIR]`: the interactive viewer (GLFW window, Dear ImGui panel).
// Without BAKE_DIR the scene is baked in the background with the default settings while the
// direct light is already on screen.

#include <memory>
#include <stdexcept>
#include <string>

#include "app/bake_options.h"
#include "app/commands.h"
#include "app/export_options.h"
#include "app/load.h"
#include "app/view_options.h"
#include "viewer/window_viewer.h"

namespace lb::app {

namespace {

struct ViewCommand {
  ViewerOptions options;  // the view-only options; the shared ones from `view`
  ViewOptionValues view{.size = "1024x768",
                        .spp = 4,
                        .passes = ViewerOptions{}.hq_passes,
                        .exposure = ViewerOptions{}.settings.tone.exposure,
                        .seed = ViewerOptions{}.hq_params.seed,
                        .max_depth = ViewerOptions{}.hq_params.max_depth,
                        .direct = "stochastic",
                        .frames = ViewerOptions{}.frames};
  BakeCommandLine bake;  // the settings of the bake made when no BAKE_DIR
};

void run_view(ViewCommand& command) {
  const ViewOptionValues& view = command.view;
  check_view_options(kView, command.view);
  ViewerOptions& options = command.options;
  options.width = view.width;
  options.height = view.height;
  options.camera = view.camera;
  options.group_weights = view.group_weights;
  options.settings.tone.exposure = view.exposure;
  options.exposure_from_camera = !view.given("--exposure");
  options.settings.term = view.term;
  options.settings.direct_mode = view.direct_mode;
  options.settings.directional = !view.no_directional;  // where the map has a band
  options.hq_params.directional = !view.no_directional;
  options.shadows.samples_per_light = view.shadow_samples;
  options.shadows.resolution = view.shadow_resolution;
  options.shader_directory = view.shaders;
  options.bake_on_load = !view.no_bake;
  options.frames = view.frames;
  if (!options.export_path.empty() && options.frames <= 0) options.frames = 1;
  options.hq_params.samples_per_side = view.samples_per_side;
  options.hq_params.final_gather = view.final_gather;
  options.hq_params.seed = view.seed;
  options.hq_params.max_depth = view.max_depth;
  options.hq_passes = view.passes;
  if (!options.hq_exr.empty() && !(options.hq && options.frames > 0))
    throw std::invalid_argument("--hq-exr: needs --hq and --frames");
  // Automation waits for a film with all its passes: give it an end.
  if (options.hq && options.frames > 0 && options.hq_passes == 0) options.hq_passes = 1;
  check_hq_params(options.hq_params);
  options.load = scene_load_options();
  // --seed seeds the bake as well as HQ mode.
  if (view.directional || view.no_directional) command.bake.directional = view.directional;
  options.bake_settings = command.bake.request(
      view.given("--seed") ? std::optional(view.seed) : std::nullopt);
  const int status = run_viewer(options);
  if (status != 0) throw ExitCode{status};
}

}  // namespace

void register_view(CLI::App& app) {
  auto* cmd = app.add_subcommand("view", "Interactive viewer: direct light, maps, bake in place");
  auto command = std::make_shared<ViewCommand>();
  ViewerOptions& options = command->options;
  cmd->add_option("scene", options.scene_path, "Scene file (.toml, .gltf, .glb)")->required();
  cmd->add_option("bake_dir", options.bake_dir, "Bake directory (default: bake in background)");
  add_view_options(*cmd, kView, command->view);
  cmd->add_option(
      "--screenshot", options.screenshot,
      "With --frames: save the last frame as PNG (add --hide-panel for the view alone)");
  cmd->add_flag("--hide-panel", options.hide_panel, "Hide the ImGui panel (key Tab toggles it)");
  cmd->add_flag("--log-actions", options.log_actions,
                "Print a line per key tap: what it did and the camera after it (automation)");
  cmd->add_option("--export", options.export_path,
                  "Press the panel's Export button with this .glb/.gltf once loaded and baked, "
                  "then close (after --frames frames, default 1)");
  // The Export panel's first values, as `lightbake export` takes them (--directional is the
  // view's own: it bakes and draws the bands, and its export carries them).
  add_export_options(*cmd, options.export_settings, /*with_directional=*/false);
  // HQ mode: the same names and meanings as `lightbake render`.
  cmd->add_flag("--hq", options.hq,
                "Start in HQ mode: ray traced, refining while the camera rests (key H)");
  cmd->add_option("--hq-exr", options.hq_exr,
                  "With --hq and --frames: write the HQ film (linear, float32 EXR) once it has "
                  "--passes passes, with --screenshot of that frame, then show raster and close");
  add_bake_options(*cmd, command->bake, kBakeFirstGroup, /*with_seed=*/false);
  cmd->callback([command] { run_view(*command); });
}

}  // namespace lb::app
