#pragma once
// The interactive viewer: a GLFW window with a Dear ImGui panel over the Renderer. Loading the
// scene and baking run on background threads, so the window never freezes.

#include <optional>
#include <string>

#include "bake/export/export_settings.h"
#include "bake/hq/hq_render.h"
#include "bake/io/scene_load.h"
#include "bake/pipeline/bake.h"
#include "bake/pipeline/bake_settings.h"
#include "viewer/render_settings.h"
#include "viewer/shader_program.h"

namespace lb {

struct ViewerOptions {
  std::string scene_path;
  SceneLoadOptions load;  // --allow-outside-uris
  std::string bake_dir;   // load this bake; empty: bake with `bake` params after loading
  bool bake_on_load = true;
  // The bake's settings as the command line asked (bake/pipeline/bake_settings.h); resolved
  // into `bake` for the scene once it loads, which the panel then edits.
  BakeSettingsRequest bake_settings;
  BakeParams bake;
  std::string camera;              // scene camera name or index, 'fit'; empty: the first
  // The light groups' starting weights (`--group-weights` text; the panel's sliders move them).
  std::string group_weights;
  int width = 1024;
  int height = 768;
  RenderSettings settings;
  bool exposure_from_camera = true;  // start at the chosen camera's exposure, not settings'
  ShadowSettings shadows;
  std::string shader_directory = default_shader_directory();
  // Automation (tests, documentation): after `frames` frames with the scene shown (and the
  // bake finished, when one runs) save the window's back buffer to `screenshot` (PNG, tone
  // mapped on the GPU; with the panel unless hide_panel) and close. frames = 0: run until
  // the window is closed.
  int frames = 0;
  std::string screenshot;
  bool hide_panel = false;
  // HQ mode (viewer/hq_view.h): on at start (key H and the panel toggle it); the renderer's
  // settings as `lightbake render` takes them (width and height are the window's), and the
  // passes after which refining stops (0: never).
  bool hq = false;
  HqParams hq_params;
  int hq_passes = 0;
  // With hq and frames > 0: once the HQ film shown has hq_passes passes (at least 1), write its
  // average (linear radiance, float32 EXR) to `hq_exr` and the screenshot (of that HQ frame),
  // then switch back to raster and close after `frames` more frames.
  std::string hq_exr;
  // With frames > 0: once loaded and baked, press the panel's Export button with this path
  // and wait for it before counting frames; a refused or failed export gives status 1.
  std::string export_path;
  // The Export panel's first values (view's export options: `lightbake export`'s words).
  ExportSettings export_settings;
  // Print a line per key tap: the key, what it did, the camera after it (tests that drive
  // the window with xdotool read them).
  bool log_actions = false;
};

// Runs until the window closes; returns the process exit status. Errors (no display, bad
// scene) are printed as one line and give 1.
int run_viewer(const ViewerOptions& options);

}  // namespace lb
