#pragma once
// The options render, reference, snapshot and view share, in one table (view_options.cpp), as
// bake/pipeline/bake_settings.h is for the bake's: each entry its name, the commands it applies
// to, its help and the value it binds. A command binds its subset in one call and has the
// table check the values after parsing, with one-line errors naming the option.

#include <CLI/CLI.hpp>
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "bake/io/image_io.h"
#include "bake/reference/reference.h"
#include "viewer/render_settings.h"
#include "viewer/shader_program.h"

namespace lb::app {

enum ViewOptionCommand : unsigned { kRender = 1u, kReference = 2u, kSnapshot = 4u, kView = 8u };

// render: from this many samples per pixel the final gather (1 ray a sample) wins per pixel as
// well as in bias against the reference; below, its noise costs more than interpolation's bias
// (bench/results/LOG.md, "the final gather": Cornell box MRE 0.032 vs 0.040 at 256 spp, 0.055
// vs 0.041 at 64). The default of render's --final-gather.
inline constexpr int kAutoGatherSpp = 256;

// What the options parse into. A command sets its own defaults where they differ from these
// before binding (they show in --help); check_view_options fills the parsed fields.
struct ViewOptionValues {
  std::string output{};
  std::string size = "640x480";  // WIDTHxHEIGHT
  std::string camera{};          // name or index, or 'fit'; "" = the scene's first
  int spp = 16;                  // render, view: a square; reference: passes
  int passes = 1;                // render: >= 1; view (HQ mode): 0 = no end
  float exposure = 0.0f;         // stops; the camera's unless given
  std::string tone = "aces";
  std::string terms = "all";  // render: a list of direct,map,radiosity; the others: one name
  uint64_t seed = 1;
  int max_depth = 16;
  int final_gather = 0;
  bool quiet = false;
  bool force = false;
  std::string group_weights{};
  // The raster (snapshot, view).
  std::string direct = "full";
  int frames = 0;  // snapshot: >= 1
  bool no_bake = false;
  bool directional = false;     // accepted: the band is drawn wherever there is one
  bool no_directional = false;  // the map as it is (L0), without its L1 band
  int shadow_samples = 0;
  int shadow_resolution = 0;
  std::string shaders = default_shader_directory();

  // Parsed by check_view_options.
  int width = 0, height = 0;
  ToneCurve tone_curve = ToneCurve::aces;
  int samples_per_side = 1;  // render, view: sqrt(spp)
  bool render_direct = false, render_map = false, render_radiosity = false;  // render's terms
  reference::Terms reference_terms = reference::Terms::all;
  Term term = Term::all;  // snapshot, view
  DirectMode direct_mode = DirectMode::full;

  std::vector<std::pair<std::string_view, CLI::Option*>> options{};  // bound, by table name
  // After parsing: whether the option named `name` (the table's, e.g. "--exposure") was given.
  bool given(std::string_view name) const;
};

// Adds the table's options for `command` to `cmd`, bound to `values`.
void add_view_options(CLI::App& cmd, ViewOptionCommand command, ViewOptionValues& values);

// Checks `values` for `command` after parsing and fills the parsed fields; throws
// std::invalid_argument with one line naming the option ("--size '0x1': ...").
void check_view_options(ViewOptionCommand command, ViewOptionValues& values);

}  // namespace lb::app
