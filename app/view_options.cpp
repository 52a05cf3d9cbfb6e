#include "app/view_options.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "app/cli_parse.h"
#include "app/group_weights_option.h"
#include "app/thread_option.h"

namespace lb::app {

namespace {

using Values = ViewOptionValues;

struct ViewOption {
  const char* name;  // CLI11's: "-o,--output", "--size"
  unsigned commands;
  const char* help;
  CLI::Option* (*bind)(CLI::App&, Values&, const ViewOption&);
};

// A value shown with its default in --help, or (Shown false) one whose default the help says.
template <auto Field, bool Shown = true>
CLI::Option* value(CLI::App& cmd, Values& v, const ViewOption& o) {
  CLI::Option* option = cmd.add_option(o.name, v.*Field, o.help);
  return Shown ? option->capture_default_str() : option;
}

template <auto Field>
CLI::Option* flag(CLI::App& cmd, Values& v, const ViewOption& o) {
  return cmd.add_flag(o.name, v.*Field, o.help);
}

CLI::Option* required_output(CLI::App& cmd, Values& v, const ViewOption& o) {
  return cmd.add_option(o.name, v.output, o.help)->required();
}

// render: `--final-gather` alone means 1 ray; not given, it is automatic (cmd_render.cpp).
CLI::Option* render_final_gather(CLI::App& cmd, Values& v, const ViewOption& o) {
  return cmd.add_option(o.name, v.final_gather, o.help)->expected(0, 1)->default_str("1");
}

CLI::Option* shadow_resolution(CLI::App& cmd, Values& v, const ViewOption& o) {
  return value<&Values::shadow_resolution>(cmd, v, o)->check(CLI::Range(0, 4096));
}

CLI::Option* group_weights(CLI::App& cmd, Values& v, const ViewOption&) {
  add_group_weights_option(cmd, v.group_weights);
  return cmd.get_option("--group-weights");
}

CLI::Option* threads(CLI::App& cmd, Values&, const ViewOption&) {
  return add_threads_option(cmd);
}

static_assert(kAutoGatherSpp == 256, "render --final-gather's help below says 256");

constexpr unsigned kImages = kRender | kReference | kSnapshot;  // commands that write an image
constexpr unsigned kRaster = kSnapshot | kView;

// Commands differ in a name's meaning or default: one entry each (their sets are disjoint).
const ViewOption kOptions[] = {
    {"-o,--output", kRender | kReference, "Image to write (.exr linear, .png tone mapped)",
     value<&Values::output>},
    {"-o,--output", kSnapshot, "Output image, .png (tone mapped) or .exr", required_output},
    {"--size", kImages, "Image size WIDTHxHEIGHT", value<&Values::size>},
    {"--size", kView, "Window size WIDTHxHEIGHT", value<&Values::size>},
    {"--camera", kImages | kView, "Camera name or index, or 'fit' (default: the scene's first)",
     value<&Values::camera, false>},
    {"--spp", kRender, "Samples per pixel per pass, a square (16 = 4x4)", value<&Values::spp>},
    {"--spp", kView, "HQ samples per pixel per pass, a square (4 = 2x2)", value<&Values::spp>},
    {"--spp", kReference, "Samples (eye paths) per pixel, one per pass", value<&Values::spp>},
    {"--passes", kRender, "Passes of --spp samples, accumulated", value<&Values::passes>},
    {"--passes", kView, "HQ passes before refining stops (0: no end)", value<&Values::passes>},
    {"--exposure", kRender | kReference, "PNG exposure, stops (default: the camera's)",
     value<&Values::exposure, false>},
    {"--exposure", kRaster, "Exposure, stops (default: the camera's)",
     value<&Values::exposure, false>},
    {"--tone", kImages, "PNG tone curve: clamp, reinhard, aces", value<&Values::tone>},
    {"--terms", kRender, "Debug: the diffuse terms to sum, any of direct,map,radiosity",
     value<&Values::terms>},
    {"--terms", kReference,
     "all, or direct: only light reaching the first diffuse surface from a light",
     value<&Values::terms>},
    {"--terms", kSnapshot,
     "all, or one term alone: direct, caustic, radiosity, ambient, specular, normals, "
     "texel_density, patches, reflectance, baked (all baked light, no direct)",
     value<&Values::terms>},
    {"--terms", kView, "Initial output (see snapshot --terms)", value<&Values::terms>},
    {"--seed", kRender, "Random seed (bake and render)", value<&Values::seed>},
    {"--seed", kView, "Random seed (bake and HQ)", value<&Values::seed>},
    {"--seed", kReference, "Random seed", value<&Values::seed>},
    {"--max-depth", kRender, "Specular bounces per viewing path", value<&Values::max_depth>},
    {"--max-depth", kView, "HQ specular bounces per path", value<&Values::max_depth>},
    {"--max-depth", kReference, "Scattering vertices before a path is dropped (guard)",
     value<&Values::max_depth>},
    {"--final-gather", kRender,
     "Soft light gathered from the bake with N rays per diffuse hit, instead of interpolated "
     "vertex radiosity (0: off; the flag alone: 1; default: 1 from 256 samples per pixel, "
     "else 0)",
     render_final_gather},
    {"--final-gather", kView,
     "HQ soft light gathered with N rays per diffuse hit (0: interpolated; note `render` turns "
     "it on by itself from 256 spp)",
     value<&Values::final_gather>},
    {"-q,--quiet", kImages, "No progress output", flag<&Values::quiet>},
    {"--force", kImages,
     "Replace the image (and its .json report) even if lightbake did not write them",
     flag<&Values::force>},
    {"--group-weights", kRender | kSnapshot, nullptr, group_weights},
    {"--group-weights", kView,
     "Light groups' starting weights, e.g. day=0.3,night=2 (the panel's sliders move them)",
     value<&Values::group_weights, false>},
    {"--no-bake", kRaster, "Do not bake (when no BAKE_DIR): the plain scene, direct light only",
     flag<&Values::no_bake>},
    {"--directional", kRaster | kRender,
     "The default: where the map has an L1 band (bake --directional, export --directional), take "
     "it at the shading normal, bump and normal maps included",
     flag<&Values::directional>},
    {"--no-directional", kRaster | kRender,
     "Draw the map as it is (its L0), without its L1 band", flag<&Values::no_directional>},
    {"--direct", kSnapshot,
     "Direct light: full (every light's shadows, exact) or stochastic (one light per pixel and "
     "frame, --frames frames averaged)",
     value<&Values::direct>},
    {"--direct", kView,
     "Direct light: stochastic (one light per pixel while moving, refined to the full "
     "evaluation while still) or full (every light's shadows every frame)",
     value<&Values::direct>},
    {"--frames", kSnapshot, "With --direct stochastic: frames averaged (their running mean)",
     value<&Values::frames>},
    {"--frames", kView, "Close after this many frames once loaded and baked (0: run until closed)",
     value<&Values::frames>},
    {"--shadow-samples", kRaster, "Shadow cubes per light (0 = automatic)",
     value<&Values::shadow_samples>},
    {"--shadow-resolution", kRaster,
     "Shadow map face size, texels (0 = automatic: 512, more for thin casters far from a "
     "light)",
     shadow_resolution},
    {"--shaders", kRaster,
     "Read the shaders from this directory (shader work; default: built in)",
     value<&Values::shaders, false>},
    {"--threads", kImages | kView, nullptr, threads},
};

// Rethrows what `parse` throws as one line naming the option (unless it does already).
template <typename Parse>
auto named(const char* option, const std::string& text, const char* expected, Parse parse) {
  try {
    return parse(text);
  } catch (const std::invalid_argument&) {
    throw std::invalid_argument(std::string(option) + ": expected " + expected + ", got '" +
                                text + "'");
  }
}

void parse_render_terms(Values& v) {
  v.render_direct = v.render_map = v.render_radiosity = false;
  size_t start = 0;
  while (start <= v.terms.size()) {
    const size_t comma = std::min(v.terms.find(',', start), v.terms.size());
    const std::string term = v.terms.substr(start, comma - start);
    if (term == "direct")
      v.render_direct = true;
    else if (term == "map")
      v.render_map = true;
    else if (term == "radiosity")
      v.render_radiosity = true;
    else
      throw std::invalid_argument("--terms: expected a list of direct, map and radiosity, got '" +
                                  v.terms + "'");
    start = comma + 1;
  }
}

}  // namespace

bool ViewOptionValues::given(std::string_view name) const {
  for (const auto& [bound, option] : options)
    if (bound == name) return option->count() > 0;
  return false;
}

void add_view_options(CLI::App& cmd, ViewOptionCommand command, ViewOptionValues& values) {
  for (const ViewOption& option : kOptions)
    if (option.commands & command)
      values.options.emplace_back(option.name, option.bind(cmd, values, option));
}

void check_view_options(ViewOptionCommand command, ViewOptionValues& v) {
  parse_size(v.size, v.width, v.height);
  if (command & (kRender | kView)) v.samples_per_side = parse_samples_per_side(v.spp);
  if (command & kImages)
    v.tone_curve = named("--tone", v.tone, "clamp, reinhard or aces", parse_tone_curve);
  if (command == kRender && v.passes < 1) throw std::invalid_argument("--passes: must be at least 1");
  if (command == kView && v.passes < 0)
    throw std::invalid_argument("--passes: must be 0 (no end) or more");
  if (command == kSnapshot && v.frames < 1)
    throw std::invalid_argument("--frames: must be 1 or more");
  if (command == kRender) parse_render_terms(v);
  if (v.directional && v.no_directional)
    throw std::invalid_argument("--directional, --no-directional: give one");
  if (command == kReference)
    v.reference_terms = named("--terms", v.terms, "all or direct", [](const std::string& t) {
      if (t == "all") return reference::Terms::all;
      if (t == "direct") return reference::Terms::direct;
      throw std::invalid_argument(t);
    });
  if (command & kRaster) {
    try {
      v.term = parse_term(v.terms);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string("--terms: ") + e.what());
    }
    v.direct_mode = named("--direct", v.direct, "full or stochastic", parse_direct_mode);
  }
}

}  // namespace lb::app
