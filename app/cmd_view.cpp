// `lightbake view SCENE [BAKE_DIR]`: the interactive viewer (GLFW window, Dear ImGui panel).
// Without BAKE_DIR the scene is baked in the background with the default settings while the
// direct light is already on screen.

#include <memory>
#include <stdexcept>
#include <string>

#include "app/bake_options.h"
#include "app/cli_parse.h"
#include "app/commands.h"
#include "app/load.h"
#include "app/thread_option.h"
#include "viewer/window_viewer.h"

namespace lb::app {

namespace {

struct ViewCommand {
  ViewerOptions options;
  std::string size = "1024x768";
  std::string term = "all";
  std::string direct = "stochastic";
  bool no_bake = false;
  int spp = 4;
  int final_gather = 0;
  BakeCommandLine bake;  // the settings of the bake made when no BAKE_DIR
  bool seed_given = false;
};

void run_view(ViewCommand& command) {
  ViewerOptions& options = command.options;
  parse_size(command.size, options.width, options.height);
  options.settings.term = parse_term(command.term);
  options.settings.direct_mode = parse_direct_mode(command.direct);
  options.bake_on_load = !command.no_bake;
  if (!options.export_path.empty() && options.frames <= 0) options.frames = 1;
  options.hq_params.samples_per_side = parse_samples_per_side(command.spp);
  options.hq_params.final_gather = command.final_gather;
  if (options.hq_passes < 0) throw std::invalid_argument("--passes: must be 0 (no end) or more");
  if (!options.hq_exr.empty() && !(options.hq && options.frames > 0))
    throw std::invalid_argument("--hq-exr: needs --hq and --frames");
  // Automation waits for a film with all its passes: give it an end.
  if (options.hq && options.frames > 0 && options.hq_passes == 0) options.hq_passes = 1;
  check_hq_params(options.hq_params);
  options.load = scene_load_options();
  // --seed seeds the bake as well as HQ mode.
  options.bake_settings = command.bake.request(
      command.seed_given ? std::optional(options.hq_params.seed) : std::nullopt);
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
  cmd->add_option("--camera", options.camera, "Scene camera name or index, or 'fit'");
  cmd->add_option("--group-weights", options.group_weights,
                  "Light groups' starting weights, e.g. day=0.3,night=2 (the panel's sliders "
                  "move them)");
  cmd->add_option("--size", command->size, "Window size WIDTHxHEIGHT")->capture_default_str();
  auto* exposure = cmd->add_option("--exposure", options.settings.tone.exposure,
                                   "Exposure, stops (default: the camera's)");
  cmd->add_option("--terms", command->term, "Initial output (see snapshot --terms)");
  cmd->add_flag("--no-bake", command->no_bake, "Do not bake on start (direct light only)");
  cmd->add_flag("--directional", options.settings.directional,
                "A directional export (export --directional): take its lightmap's L1 band at "
                "the shading normal, bump and normal maps included");
  cmd->add_option("--direct", command->direct,
                  "Direct light: stochastic (one light per pixel while moving, refined to the "
                  "full evaluation while still) or full (every light's shadows every frame)")
      ->capture_default_str();
  cmd->add_option("--shadow-samples", options.shadows.samples_per_light,
                  "Shadow cubes per light (0 = automatic)");
  cmd->add_option("--shadow-resolution", options.shadows.resolution,
                  "Shadow map face size, texels (0 = automatic: 512, more for thin casters far "
                  "from a light)")
      ->check(CLI::Range(0, 4096));
  cmd->add_option("--shaders", options.shader_directory,
                  "Read the shaders from this directory (shader work; default: built in)");
  cmd->add_option("--frames", options.frames,
                  "Close after this many frames once loaded and baked (0: run until closed)");
  cmd->add_option(
      "--screenshot", options.screenshot,
      "With --frames: save the last frame as PNG (add --hide-panel for the view alone)");
  cmd->add_flag("--hide-panel", options.hide_panel, "Hide the ImGui panel (key Tab toggles it)");
  cmd->add_flag("--log-actions", options.log_actions,
                "Print a line per key tap: what it did and the camera after it (automation)");
  cmd->add_option("--export", options.export_path,
                  "Press the panel's Export button with this .glb/.gltf once loaded and baked, "
                  "then close (after --frames frames, default 1)");
  // HQ mode: the same names and meanings as `lightbake render`.
  cmd->add_flag("--hq", options.hq,
                "Start in HQ mode: ray traced, refining while the camera rests (key H)");
  cmd->add_option("--spp", command->spp, "HQ samples per pixel per pass, a square (4 = 2x2)")
      ->capture_default_str();
  cmd->add_option("--passes", options.hq_passes, "HQ passes before refining stops (0: no end)")
      ->capture_default_str();
  auto* seed = cmd->add_option("--seed", options.hq_params.seed, "Random seed (bake and HQ)")
                   ->capture_default_str();
  cmd->add_option("--max-depth", options.hq_params.max_depth, "HQ specular bounces per path")
      ->capture_default_str();
  cmd->add_option("--final-gather", command->final_gather,
                  "HQ soft light gathered with N rays per diffuse hit (0: interpolated; note "
                  "`render` turns it on by itself from 256 spp)")
      ->capture_default_str();
  cmd->add_option("--hq-exr", options.hq_exr,
                  "With --hq and --frames: write the HQ film (linear, float32 EXR) once it has "
                  "--passes passes, with --screenshot of that frame, then show raster and close");
  add_bake_options(*cmd, command->bake, kBakeFirstGroup, /*with_seed=*/false);
  add_threads_option(*cmd);
  cmd->callback([command, exposure, seed] {
    command->seed_given = seed->count() > 0;
    command->options.exposure_from_camera = exposure->count() == 0;
    run_view(*command);
  });
}

}  // namespace lb::app
