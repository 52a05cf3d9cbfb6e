// Viewer frame time on Mesa llvmpipe (OSMesa, no GPU) at 1024 x 768, for the paper's
// Figures 5, 6 and 8 (the default room) and Figure 7, against the yardstick of the same
// scene drawn with a flat shader (one colour per material, no lighting) in the same run;
// fig8_room_lamps adds a point, a spot and a directional lamp to the room.
// The ratio full/flat is the cost of the per-fragment direct light (exact polygon
// irradiance), the soft-shadow lookups and the maps. frame_stochastic is the viewer's default:
// every light's exact unshadowed term but the shadow lookups of one light per fragment
// (shaders/light_pick.glsl), the still camera's frames accumulating. converge/fig5 counts the
// still-camera frames the stochastic mode needs until its image is within 1/255 of the full
// one in every display value (lb::max_display_difference), and their frame time.
//
// level/inside and level/above draw bench/make_level.py's level (92k triangles, generated
// into the build tree; LIGHTBAKE_BENCH_LEVEL=FILE draws another, e.g. the 1M one) from inside
// the first room looking along the grid and from above the whole level, in the stochastic
// mode (the moving camera's frame, frame_stochastic), each iteration one
// frame with nothing culled, one with frustum culling alone (frustum_ms) and one with the
// depth pre-pass too (culled_ms): `speedup` = unculled / culled frame time, in one run. Its
// counters also give set_scene's seconds (upload, shadow cubes with frustum and occlusion
// culling, and unculled_shadow_build_s without), the shadow cubes' triangles drawn of all, and the
// GPU memory of geometry and shadow maps. Light lists (viewer/light_lists.h): culled_ms and
// full_ms are with them, culled_no_lists_ms and full_no_lists_ms the same frames without
// (full_differing_values counts the full frames' values that differ: 0 expected); the upload
// is timed without lists (set_scene_no_lists_s, shadow_build_no_lists_s) and with; and
// lights_chunk_mean / max, list_queries, lists_finish_s describe the lists. lists/bundled
// renders every bundled scene, plain and baked (draft), with lists on and off in full mode and
// counts differing values.
//
// moving/inside and moving/above: the same level and views, sequences of 12 frames with the
// camera stepping 2 cm a frame, mean ms a frame: the stochastic frame a window draws while
// moving (window_viewer.cpp: the renderer at 1024 / d x 768 / d, d = 2, 3, 4 adapted to the
// frame time; d = 1 the full size; present()'s scaling up not timed) with the camera pass's
// occlusion culling off (off_dK_ms), on with its schedule (occ_dK_ms; the first frame of a
// sequence probes; `_queried` counts the frames that queried) and on with the planar mirrors
// read from the environment capture (lod_dK_ms, d > 1; lodnp_dK_ms the same without the
// depth pre-pass, so without occlusion culling), and the flat frame off and on. Each
// also in process CPU time (`_cpu_ms`, every llvmpipe thread); planar passes a frame; and
// differing_values between each sequence's last frame off and on (0 expected).
//
// groups/fig8_room_lamps: the room and its lamps in two light groups, frames at slider weights
// against the same room without groups and at the default weights (light_groups_frame below).
//
//   build/bench/bench_viewer --benchmark_counters_tabular=true
// LP_NUM_THREADS sets llvmpipe's rasteriser threads (default: the core count).

#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>
#include <cmath>

#include "bake/camera.h"
#include "bake/io/scene_load.h"
#include "bake/light_groups.h"
#include "bake/pipeline/bake.h"
#include "viewer/mesh_detail.h"
#include "viewer/offscreen_context.h"
#include "viewer/renderer.h"
#include "viewer/snapshot.h"

namespace {

constexpr int kWidth = 1024, kHeight = 768;

// One OSMesa context for the process; one uploaded scene per file, shared by its two
// benchmarks.
lb::OffscreenContext& context() {
  static lb::OffscreenContext instance;
  return instance;
}

// The Figure 8 room with one lamp of each kind as well (a point lamp, a spot on the block, a
// sun through the closed ceiling, so in shadow): what the lamps and their maps cost.
void add_lamps(lb::Scene& scene) {
  lb::Lamp point;
  point.kind = lb::LampKind::point;
  point.position = {1.2f, 2.2f, 1.0f};
  point.intensity = lb::vec3(5.0f);
  lb::Lamp spot = point;
  spot.kind = lb::LampKind::spot;
  spot.position = {1.5f, 2.5f, -1.5f};
  spot.direction = glm::normalize(lb::vec3(-2.3f, -2.1f, 0.6f));
  spot.inner_cone = 0.3f;
  spot.outer_cone = 0.5f;
  lb::Lamp sun;
  sun.kind = lb::LampKind::directional;
  sun.direction = glm::normalize(lb::vec3(0.3f, -1.0f, 0.2f));
  sun.intensity = lb::vec3(100.0f);
  scene.lights = {point, spot, sun};
}

struct Fixture {
  lb::Renderer renderer;
  lb::ViewCamera camera;
  float exposure = 0.0f;  // the scene camera's, stops
  size_t triangles = 0;
  explicit Fixture(const std::string& file)
      : renderer((context(), lb::default_shader_directory())) {
    const bool lamps = file.ends_with("+lamps");
    const std::string path = lamps ? file.substr(0, file.size() - 6) : file;
    lb::Scene scene = lb::load_scene(std::string(LIGHTBAKE_SOURCE_DIR) + "/scenes/" + path).scene;
    if (lamps) add_lamps(scene);
    renderer.set_scene(scene, nullptr);
    camera = lb::choose_camera(scene, "");
    exposure = lb::select_camera(scene, "").exposure;
    triangles = lb::triangle_count(scene);
  }
};

Fixture& fixture(const std::string& file) {
  static std::string current;
  static std::unique_ptr<Fixture> instance;
  if (current != file) {
    instance.reset();
    instance = std::make_unique<Fixture>(file);
    current = file;
  }
  return *instance;
}

enum class Shading { flat, full, stochastic };

void frame(benchmark::State& state, const std::string& file, Shading shading) {
  Fixture& f = fixture(file);
  const bool flat = shading == Shading::flat;
  lb::RenderSettings settings;
  if (shading == Shading::stochastic) {
    // What every frame costs while the camera moves: refinement off, so a still camera does
    // not stop drawing once exact.
    settings.direct_mode = lb::DirectMode::stochastic;
    settings.refine_bands = 0;
  }
  // One untimed frame first: llvmpipe compiles each shader variant on its first draw.
  if (flat)
    f.renderer.render_flat(f.camera, kWidth, kHeight);
  else
    f.renderer.render(f.camera, kWidth, kHeight, settings);
  glFinish();
  for (auto _ : state) {
    if (flat) {
      f.renderer.render_flat(f.camera, kWidth, kHeight);
    } else {
      f.renderer.render(f.camera, kWidth, kHeight, settings);
    }
    glFinish();  // llvmpipe renders when flushed; time the whole frame
  }
  state.counters["triangles"] = double(f.triangles);
  state.counters["shadow_cubes"] = f.renderer.stats().shadow_cubes;
  state.counters["shadow_build_s"] = f.renderer.stats().shadow_build_seconds;
}

void register_scene(const std::string& label, const std::string& file) {
  const std::pair<const char*, Shading> kinds[] = {{"frame_flat/", Shading::flat},
                                                   {"frame_full/", Shading::full},
                                                   {"frame_stochastic/", Shading::stochastic}};
  for (const auto& [prefix, shading] : kinds) {
    benchmark::RegisterBenchmark((prefix + label).c_str(),
                                 [file, shading](benchmark::State& s) { frame(s, file, shading); })
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime()  // the work is llvmpipe's threads, not this one's CPU time
        ->MinTime(1.0);
  }
}

// Still-camera frames in the viewer's stochastic mode until the image is within 1/255 of the
// full one in every display value (tone map: the scene camera's exposure, the default curve);
// the time is the frames' own (glFinish each), not the read-backs that check them. With the
// default refine_bands the full evaluation replaces the first frame's estimate band by band;
// `running_mean_*` are the same frames' plain running mean (refine_bands 0) after 16 and 64.
struct Convergence {
  int frames = 0;
  double seconds = 0.0, first = 0.0, last = 1.0;
};

Convergence still_frames(Fixture& f, const lb::Image& full, const lb::ToneMap& tone,
                         lb::RenderSettings settings, int max_frames) {
  f.renderer.render_flat(f.camera, kWidth, kHeight);  // restarts the accumulation
  Convergence c;
  while (c.frames < max_frames && c.last > 1.0 / 255.0) {
    const auto start = std::chrono::steady_clock::now();
    f.renderer.render(f.camera, kWidth, kHeight, settings);
    glFinish();
    c.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ++c.frames;
    c.last = lb::max_display_difference(f.renderer.read_radiance(), full, tone);
    if (c.frames == 1) c.first = c.last;
  }
  return c;
}

void converge(benchmark::State& state, const std::string& file) {
  Fixture& f = fixture(file);
  lb::ToneMap tone;
  tone.exposure = f.exposure;
  for (auto _ : state) {
    lb::RenderSettings settings;
    f.renderer.render(f.camera, kWidth, kHeight, settings);
    const lb::Image full = f.renderer.read_radiance();
    settings.direct_mode = lb::DirectMode::stochastic;
    const Convergence refined = still_frames(f, full, tone, settings, 64);
    state.counters["frames"] = refined.frames;
    state.counters["frames_s"] = refined.seconds;
    state.counters["first_frame_diff255"] = 255.0 * refined.first;
    state.counters["final_diff255"] = 255.0 * refined.last;
    settings.refine_bands = 0;
    state.counters["running_mean_16_diff255"] =
        255.0 * still_frames(f, full, tone, settings, 16).last;
    state.counters["running_mean_64_diff255"] =
        255.0 * still_frames(f, full, tone, settings, 64).last;
  }
}

// ---- Light lists: the same bits on the bundled scenes ------------------------------------

// Values (floats of the RGB radiance) that differ between a and b.
size_t differing_values(const lb::Image& a, const lb::Image& b) {
  if (a.pixels.size() != b.pixels.size()) return std::max(a.pixels.size(), b.pixels.size());
  size_t n = 0;
  for (size_t i = 0; i < a.pixels.size(); ++i) n += a.pixels[i] != b.pixels[i];
  return n;
}

// Every bundled scene, plain and baked (draft quality), from its first camera in full mode:
// values differing between lists on and off (viewer/light_lists.h), summed; `dropping` counts
// the scene variants whose lists leave out any light.
void lists_bundled(benchmark::State& state) {
  context();
  lb::Renderer renderer;
  size_t differing = 0;
  int variants = 0, dropping = 0;
  for (auto _ : state) {
    for (const auto& entry :
         std::filesystem::directory_iterator(std::string(LIGHTBAKE_SOURCE_DIR) + "/scenes")) {
      if (entry.path().extension() != ".toml") continue;
      const lb::Scene scene = lb::load_scene(entry.path().string()).scene;
      lb::BakeParams params;
      lb::apply_quality(scene, lb::Quality::draft, params);
      const lb::BakeResult bake = lb::bake_scene(scene, params);
      for (const bool baked : {false, true}) {
        renderer.set_culling({});
        renderer.set_scene(scene, baked ? &bake : nullptr);
        const lb::ViewCamera camera = lb::choose_camera(scene, "");
        lb::Image images[2];
        for (const bool lists : {true, false}) {
          lb::Renderer::Culling culling;
          culling.light_lists = lists;
          renderer.set_culling(culling);
          renderer.render(camera, 320, 240, lb::RenderSettings{});
          images[lists] = renderer.read_radiance();
        }
        const size_t d = differing_values(images[0], images[1]);
        const int lights = int(renderer.scene().lights().lights.size());
        dropping += renderer.stats().lights_per_chunk_mean < double(lights);
        std::printf("%s%s: %d lights, %.2f a chunk (max %d), %zu values differ\n",
                    entry.path().filename().c_str(), baked ? " baked" : "", lights,
                    renderer.stats().lights_per_chunk_mean, renderer.stats().lights_per_chunk_max,
                    d);
        differing += d;
        ++variants;
      }
    }
  }
  state.counters["variants"] = variants;
  state.counters["dropping"] = dropping;
  state.counters["differing_values"] = double(differing);
}

// ---- The big level: culled against unculled ---------------------------------------------

std::string level_path() {
  const char* path = std::getenv("LIGHTBAKE_BENCH_LEVEL");
  return path && *path ? path : LIGHTBAKE_BENCH_LEVEL;
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

struct Level {
  lb::Renderer renderer;
  lb::ViewCamera inside, above;
  size_t triangles = 0, meshes = 0;
  double load_s = 0.0, set_scene_s = 0.0, unculled_shadow_build_s = 0.0;
  double set_scene_no_lists_s = 0.0, shadow_build_no_lists_s = 0.0;
  Level() : renderer((context(), lb::default_shader_directory())) {
    auto start = std::chrono::steady_clock::now();
    const lb::Scene scene = lb::load_scene(level_path()).scene;
    load_s = seconds_since(start);
    triangles = lb::triangle_count(scene);
    meshes = scene.meshes.size();
    start = std::chrono::steady_clock::now();
    // The shadow cubes without culling, to compare (LIGHTBAKE_BENCH_CULLED_ONLY=1 skips it).
    if (!std::getenv("LIGHTBAKE_BENCH_CULLED_ONLY")) {
      renderer.set_culling({false, false, false, false});
      renderer.set_scene(scene, nullptr);
      glFinish();
      unculled_shadow_build_s = renderer.stats().shadow_build_seconds;
    }
    // Culled, without light lists: what the lists add to the upload.
    start = std::chrono::steady_clock::now();
    renderer.set_culling({true, true, true, false});
    renderer.set_scene(scene, nullptr);
    glFinish();
    set_scene_no_lists_s = seconds_since(start);
    shadow_build_no_lists_s = renderer.stats().shadow_build_seconds;
    start = std::chrono::steady_clock::now();
    renderer.set_culling({});
    renderer.set_scene(scene, nullptr);
    glFinish();
    set_scene_s = seconds_since(start);
    inside = lb::choose_camera(scene, "overview");  // in room (0, 0), along the diagonal
    // Above the middle, the whole level in view: what culling cannot help.
    const lb::Bounds bounds = lb::scene_bounds(scene);
    const lb::vec3 centre = 0.5f * (bounds.min + bounds.max), extent = bounds.extent();
    above.target = centre;
    above.position = centre + lb::vec3(0.0f, 0.75f * std::max(extent.x, extent.z), 0.3f * extent.z);
    above.vertical_fov_deg = 70.0f;
  }
};

Level& level() {
  static Level instance;
  return instance;
}

// Wall and process CPU seconds (every llvmpipe thread) of one frame.
struct FrameTime {
  double wall = 0.0, cpu = 0.0;
  void add(const FrameTime& t) {
    wall += t.wall;
    cpu += t.cpu;
  }
};

FrameTime time_frame(const std::function<void()>& draw) {
  glFinish();
  const std::clock_t cpu_start = std::clock();
  const auto start = std::chrono::steady_clock::now();
  draw();
  glFinish();
  return {seconds_since(start), double(std::clock() - cpu_start) / CLOCKS_PER_SEC};
}

FrameTime timed_frame_cpu(lb::Renderer& renderer, const lb::ViewCamera& camera,
                          lb::Renderer::Culling culling, bool full = false, int width = kWidth,
                          int height = kHeight) {
  renderer.set_culling(culling);
  // The viewer's default while the camera moves (frame_stochastic above), or one full frame.
  lb::RenderSettings settings;
  settings.direct_mode = full ? lb::DirectMode::full : lb::DirectMode::stochastic;
  settings.refine_bands = 0;
  renderer.render_flat(camera, width, height);  // each stochastic frame a first one
  return time_frame([&] { renderer.render(camera, width, height, settings); });
}

double timed_frame(lb::Renderer& renderer, const lb::ViewCamera& camera,
                   lb::Renderer::Culling culling, bool full = false) {
  return timed_frame_cpu(renderer, camera, culling, full).wall;
}

void level_frame(benchmark::State& state, bool from_above) {
  Level& l = level();
  const lb::ViewCamera& camera = from_above ? l.above : l.inside;
  const lb::Renderer::Culling none{false, false, false, false}, frustum{true, false, true, false},
      no_lists{true, true, true, false}, both{true, true, true, true};
  timed_frame(l.renderer, camera, both);  // llvmpipe compiles the variants on first use
  timed_frame(l.renderer, camera, both, true);
  double culled = 0.0, unculled = 0.0, frustum_only = 0.0, culled_no_lists = 0.0;
  double full = 0.0, full_no_lists = 0.0;
  lb::DrawCounts counts;
  size_t differing = 0;
  for (auto _ : state) {
    unculled += timed_frame(l.renderer, camera, none);
    frustum_only += timed_frame(l.renderer, camera, frustum);
    culled_no_lists += timed_frame(l.renderer, camera, no_lists);
    culled += timed_frame(l.renderer, camera, both);
    counts = l.renderer.stats().view;
    full_no_lists += timed_frame(l.renderer, camera, no_lists, true);
    const lb::Image without = l.renderer.read_radiance();
    full += timed_frame(l.renderer, camera, both, true);
    differing += differing_values(l.renderer.read_radiance(), without);
  }
  // The flat yardstick of the same view, culled: what the geometry alone costs.
  l.renderer.set_culling({});
  l.renderer.render_flat(camera, kWidth, kHeight);
  glFinish();
  const auto flat_start = std::chrono::steady_clock::now();
  l.renderer.render_flat(camera, kWidth, kHeight);
  glFinish();
  state.counters["flat_ms"] = 1e3 * seconds_since(flat_start);
  const double n = double(state.iterations());
  state.counters["frustum_ms"] = 1e3 * frustum_only / n;
  state.counters["culled_ms"] = 1e3 * culled / n;
  state.counters["unculled_ms"] = 1e3 * unculled / n;
  // Light lists (viewer/light_lists.h): frames without them, full-mode frames, the lists.
  state.counters["culled_no_lists_ms"] = 1e3 * culled_no_lists / n;
  state.counters["full_ms"] = 1e3 * full / n;
  state.counters["full_no_lists_ms"] = 1e3 * full_no_lists / n;
  state.counters["full_differing_values"] = double(differing);
  state.counters["set_scene_no_lists_s"] = l.set_scene_no_lists_s;
  state.counters["shadow_build_no_lists_s"] = l.shadow_build_no_lists_s;
  state.counters["speedup"] = unculled / culled;
  state.counters["triangles"] = double(l.triangles);
  state.counters["meshes"] = double(l.meshes);
  state.counters["drawn_triangles"] = double(counts.triangles_drawn);
  state.counters["drawn_chunks"] = counts.chunks_drawn;
  state.counters["chunks"] = counts.chunks_total;
  state.counters["load_s"] = l.load_s;
  state.counters["set_scene_s"] = l.set_scene_s;
  const lb::FrameStats& stats = l.renderer.stats();
  state.counters["shadow_build_s"] = stats.shadow_build_seconds;
  state.counters["lists_finish_s"] = stats.light_lists_seconds;
  state.counters["list_queries"] = stats.light_list_queries;
  state.counters["lights_chunk_mean"] = stats.lights_per_chunk_mean;
  state.counters["lights_chunk_max"] = stats.lights_per_chunk_max;
  state.counters["unculled_shadow_build_s"] = l.unculled_shadow_build_s;
  state.counters["environment_s"] = stats.environment_seconds;
  state.counters["shadow_drawn_frac"] =
      double(stats.shadow_cubes_drawn.triangles_drawn) /
      double(std::max<size_t>(1, stats.shadow_cubes_drawn.triangles_total));
  state.counters["geometry_MiB"] = double(l.renderer.scene().geometry_bytes()) / (1 << 20);
  // DEPTH_COMPONENT32F, 6 faces a cube (viewer/shadow_maps.cpp).
  const double res = lb::ShadowSettings{}.resolution;
  state.counters["shadow_cubes_MiB"] = 6.0 * stats.shadow_cubes * res * res * 4.0 / (1 << 20);
}

// One moving-camera sequence: kSequence frames of width x height, the camera stepping 2 cm
// along its view each frame (so each stochastic frame is a first one, as while moving), with
// `culling` (set twice, so the occlusion schedule starts again: the first frame probes) and
// `settings`. Returns the summed time; `queried` counts the frames whose pass queried.
constexpr int kSequence = 12;
FrameTime moving_sequence(lb::Renderer& renderer, lb::ViewCamera camera,
                          lb::Renderer::Culling culling, const lb::RenderSettings& settings,
                          int width, int height, int& queried, bool flat = false) {
  lb::Renderer::Culling other = culling;
  other.camera_occlusion = !culling.camera_occlusion;
  renderer.set_culling(other);
  renderer.set_culling(culling);
  const lb::vec3 step = 0.02f * glm::normalize(camera.target - camera.position);
  FrameTime total;
  for (int f = 0; f < kSequence; ++f) {
    camera.position += step;
    camera.target += step;
    total.add(time_frame([&] {
      if (flat) {
        renderer.render_flat(camera, width, height);
      } else {
        renderer.render(camera, width, height, settings);
      }
    }));
    queried += renderer.stats().camera_occlusion_queried ? 1 : 0;
  }
  return total;
}

// Windows' frames over the same sequences: camera occlusion off (`_off`), on with its
// schedule (`_occ`), and on with the planar mirrors read from the environment capture
// (`_lod`, RenderSettings::planar_reflections off: what window_viewer now draws while moving);
// `_lodnp` as `_lod` without the depth pre-pass: whether the pre-pass pays at small sizes.
void level_moving(benchmark::State& state, bool from_above) {
  Level& l = level();
  const lb::ViewCamera& camera = from_above ? l.above : l.inside;
  lb::Renderer::Culling off, on, no_prepass;
  off.camera_occlusion = false;
  no_prepass.depth_prepass = no_prepass.camera_occlusion = false;
  lb::RenderSettings mirrors;
  mirrors.direct_mode = lb::DirectMode::stochastic;
  mirrors.refine_bands = 0;
  lb::RenderSettings lod = mirrors;
  lod.planar_reflections = false;
  struct Variant {
    const char* name;
    lb::Renderer::Culling culling;
    lb::RenderSettings settings;
  };
  const Variant variants[4] = {{"off", off, mirrors},
                               {"occ", on, mirrors},
                               {"lod", on, lod},
                               {"lodnp", no_prepass, lod}};
  constexpr int kDivisors[4] = {1, 2, 3, 4};
  for (const Variant& v : variants) {  // llvmpipe compiles each variant on first use
    l.renderer.set_culling(v.culling);
    l.renderer.render(camera, kWidth / 4, kHeight / 4, v.settings);
  }
  FrameTime frames[4][4], flat[2];
  int queried[4][4] = {}, flat_queried[2] = {}, planar_passes[4] = {};
  size_t differing = 0;
  for (auto _ : state) {
    for (int d = 0; d < 4; ++d) {
      lb::Image last[2];
      for (int v = 0; v < 4; ++v) {
        if (kDivisors[d] == 1 && v >= 2) continue;  // the still size: mirrors always
        frames[v][d].add(moving_sequence(l.renderer, camera, variants[v].culling,
                                         variants[v].settings, kWidth / kDivisors[d],
                                         kHeight / kDivisors[d], queried[v][d]));
        planar_passes[v] = l.renderer.stats().planar_passes;
        if (v < 2) last[v] = l.renderer.read_radiance();
      }
      differing += differing_values(last[0], last[1]);
    }
    for (int v = 0; v < 2; ++v) {
      flat[v].add(moving_sequence(l.renderer, camera, variants[v].culling, mirrors, kWidth,
                                  kHeight, flat_queried[v], true));
    }
  }
  l.renderer.set_culling({});
  const double n = double(state.iterations()) * kSequence;
  auto report = [&](const std::string& name, const FrameTime& t, int frames_queried) {
    state.counters[name + "_ms"] = 1e3 * t.wall / n;
    state.counters[name + "_cpu_ms"] = 1e3 * t.cpu / n;
    state.counters[name + "_queried"] = double(frames_queried) / double(state.iterations());
  };
  for (int v = 0; v < 4; ++v) {
    for (int d = 0; d < 4; ++d) {
      if (kDivisors[d] == 1 && v >= 2) continue;
      report(std::string(variants[v].name) + "_d" + std::to_string(kDivisors[d]), frames[v][d],
             queried[v][d]);
    }
    state.counters[std::string("planar_passes_") + variants[v].name] = planar_passes[v];
  }
  report("flat_off", flat[0], flat_queried[0]);
  report("flat_occ", flat[1], flat_queried[1]);
  state.counters["triangles"] = double(l.triangles);
  state.counters["differing_values"] = double(differing);
}

// The window's moving frame (camera occlusion on its schedule, mirrors from the capture) at
// 1024/d x 768/d in three variants: the clusters alone (`clusters`: no occluders first, full
// detail: the window before both), the occluders first (`occl`, viewer/occlusion_culler.h) and
// the occluders first with one pixel of geometric error allowed (`lod1`, viewer/mesh_detail.h).
// Per variant and d: mean ms and CPU ms a frame over a 12-frame sequence, the triangles its last
// frame drew. `occl_differing`: values of the last frames that differ between `clusters` and
// `occl` (must be 0); `mre`: lod1 against occl, the summed |difference| over the summed image
// (over the pixels occl lights), `off5`: the share of those pixels off by more than 5 %. The
// flat frame (1024 x 768) in the same three. `detail_build_cpu_s`, `detail_build_s`: CPU and
// wall seconds of make_scene_detail, the upload's share for the levels.
void level_detail(benchmark::State& state, bool from_above) {
  Level& l = level();
  const lb::ViewCamera& camera = from_above ? l.above : l.inside;
  lb::RenderSettings full;
  full.direct_mode = lb::DirectMode::stochastic;
  full.refine_bands = 0;
  full.planar_reflections = false;
  lb::RenderSettings lod = full;
  lod.detail_pixels = 1.0f;
  lb::Renderer::Culling clusters, occl;
  clusters.occluders_first = false;
  struct Variant {
    const char* name;
    lb::Renderer::Culling culling;
    const lb::RenderSettings* settings;
  };
  const Variant variants[3] = {{"clusters", clusters, &full}, {"occl", occl, &full},
                               {"lod1", occl, &lod}};
  for (const Variant& v : variants) {  // llvmpipe compiles each variant on first use
    l.renderer.set_culling(v.culling);
    l.renderer.render(camera, kWidth / 4, kHeight / 4, *v.settings);
  }
  FrameTime frames[3][4], flat[3];
  size_t drawn[3][4] = {}, flat_drawn[3] = {};
  double mre[4] = {}, off5[4] = {};
  size_t differing = 0;
  int queried = 0;
  for (auto _ : state) {
    for (int d = 1; d <= 4; ++d) {
      lb::Image last[3];
      for (int v = 0; v < 3; ++v) {
        frames[v][d - 1].add(moving_sequence(l.renderer, camera, variants[v].culling,
                                             *variants[v].settings, kWidth / d, kHeight / d,
                                             queried));
        drawn[v][d - 1] = l.renderer.stats().view.triangles_drawn;
        last[v] = l.renderer.read_radiance();
      }
      differing += differing_values(last[0], last[1]);
      const size_t channels = size_t(std::max(3, last[1].channels));
      double sum = 0.0, total = 0.0;
      size_t lit = 0, off = 0;
      for (size_t i = 0; i + 2 < last[1].pixels.size(); i += channels) {
        const double a = last[1].pixels[i] + last[1].pixels[i + 1] + last[1].pixels[i + 2];
        const double b = last[2].pixels[i] + last[2].pixels[i + 1] + last[2].pixels[i + 2];
        if (a <= 0.0) continue;
        ++lit;
        sum += std::abs(b - a);
        total += a;
        off += std::abs(b - a) > 0.05 * a ? 1 : 0;
      }
      mre[d - 1] = sum / std::max(total, 1e-30);
      off5[d - 1] = double(off) / double(std::max<size_t>(1, lit));
    }
    for (int v = 0; v < 3; ++v) {
      const lb::vec3 step = 0.02f * glm::normalize(camera.target - camera.position);
      lb::ViewCamera moved = camera;
      l.renderer.set_culling(variants[v].culling);
      for (int f = 0; f < kSequence; ++f) {
        moved.position += step;
        moved.target += step;
        flat[v].add(time_frame([&] {
          l.renderer.render_flat(moved, kWidth, kHeight, variants[v].settings->detail_pixels);
        }));
      }
      flat_drawn[v] = l.renderer.stats().view.triangles_drawn;
    }
  }
  l.renderer.set_culling({});
  const double n = double(state.iterations()) * kSequence;
  for (int v = 0; v < 3; ++v) {
    for (int d = 1; d <= 4; ++d) {
      const std::string name = std::string(variants[v].name) + "_d" + std::to_string(d);
      state.counters[name + "_ms"] = 1e3 * frames[v][d - 1].wall / n;
      state.counters[name + "_cpu_ms"] = 1e3 * frames[v][d - 1].cpu / n;
      state.counters[name + "_tris"] = double(drawn[v][d - 1]);
    }
    const std::string name = std::string("flat_") + variants[v].name;
    state.counters[name + "_ms"] = 1e3 * flat[v].wall / n;
    state.counters[name + "_cpu_ms"] = 1e3 * flat[v].cpu / n;
    state.counters[name + "_tris"] = double(flat_drawn[v]);
  }
  for (int d = 1; d <= 4; ++d) {
    state.counters["mre_d" + std::to_string(d)] = mre[d - 1];
    state.counters["off5_d" + std::to_string(d)] = off5[d - 1];
  }
  state.counters["occl_differing"] = double(differing);
  state.counters["triangles"] = double(l.triangles);
  state.counters["detail_triangles"] = double(l.renderer.scene().detail_triangles());
  state.counters["geometry_MiB"] = double(l.renderer.scene().geometry_bytes()) / (1 << 20);
  state.counters["set_scene_s"] = l.set_scene_s;
  const std::vector<lb::Mesh>& meshes = l.renderer.scene().scene().meshes;
  std::vector<lb::MeshChunks> chunks;
  for (const lb::Mesh& mesh : meshes) chunks.push_back(lb::make_mesh_chunks(mesh));
  const std::clock_t cpu_start = std::clock();
  const auto wall_start = std::chrono::steady_clock::now();
  benchmark::DoNotOptimize(lb::make_scene_detail(meshes, chunks));
  state.counters["detail_build_cpu_s"] = double(std::clock() - cpu_start) / CLOCKS_PER_SEC;
  state.counters["detail_build_s"] = seconds_since(wall_start);
}

// ---- light groups (issue 39) ------------------------------------------------------------
// groups/fig8_room_lamps: the room with its lamps, the ceiling panel in group `day` and the
// three lamps in `night`, baked at draft once; frames (the viewer's stochastic default, 1024 x
// 768) of the same room without groups (its own bake), of the groups at the default weights and
// at slider weights (day 0.3, night 2) as the viewer draws them (LightGroupMix::apply:
// scale_light_groups and blend_light_groups, then Renderer::update_scene), interleaved in one
// run. `sliders_vs_none` and `sliders_vs_default`: the ratios of the mean frame times (issue
// 39 asks <= 1.1); slider_move_ms: what one move of a slider costs (the blend and the upload),
// once, not per frame.
void light_groups_frame(benchmark::State& state) {
  lb::Scene plain = lb::load_scene(std::string(LIGHTBAKE_SOURCE_DIR) + "/scenes/room.toml").scene;
  add_lamps(plain);
  lb::Scene grouped = plain;
  for (lb::Material& m : grouped.materials)
    if (m.is_emitter()) m.light_group = "day";
  for (lb::Lamp& lamp : grouped.lights) lamp.light_group = "night";
  lb::BakeParams params;
  lb::apply_quality(plain, lb::Quality::draft, params);
  const lb::BakeResult plain_bake = lb::bake_scene(plain, params);
  const lb::BakeResult grouped_bake = lb::bake_scene(grouped, params);
  // As the viewer's panel: the lights scaled (a weight 0 kept at 1e-6) and the bake blended.
  struct Mix {
    lb::Scene scene;
    lb::BakeResult bake;
  };
  const auto mix = [&](const std::vector<float>& weights) {
    return Mix{lb::scale_light_groups(grouped, weights),
               lb::blend_light_groups(grouped_bake, weights)};
  };
  const Mix defaults = mix({1.0f, 1.0f});
  Mix sliders = mix({0.3f, 2.0f});
  const lb::ViewCamera camera = lb::choose_camera(plain, "");
  lb::RenderSettings settings;
  settings.direct_mode = lb::DirectMode::stochastic;
  settings.refine_bands = 0;
  struct View {
    const char* name;
    std::unique_ptr<lb::Renderer> renderer;
    FrameTime time;
  };
  View views[3] = {{"none", nullptr, {}}, {"default", nullptr, {}}, {"sliders", nullptr, {}}};
  const std::pair<const lb::Scene*, const lb::BakeResult*> shown[3] = {
      {&plain, &plain_bake}, {&defaults.scene, &defaults.bake}, {&sliders.scene, &sliders.bake}};
  context();  // the GL context before any renderer
  for (int v = 0; v < 3; ++v) {
    views[v].renderer = std::make_unique<lb::Renderer>(lb::default_shader_directory());
    views[v].renderer->set_scene(*shown[v].first, shown[v].second);
    views[v].renderer->render(camera, kWidth, kHeight, settings);  // llvmpipe compiles
  }
  // One slider move as the viewer makes it: the blend, then the upload to the same renderer.
  const std::clock_t move_cpu = std::clock();
  const auto move_start = std::chrono::steady_clock::now();
  sliders = mix({0.3f, 2.0f});
  views[2].renderer->update_scene(sliders.scene, &sliders.bake);
  glFinish();
  state.counters["slider_move_ms"] = 1e3 * seconds_since(move_start);
  state.counters["slider_move_cpu_ms"] = 1e3 * double(std::clock() - move_cpu) / CLOCKS_PER_SEC;
  constexpr int kFrames = 4;  // a view's frames in a row, then the next view's
  for (auto _ : state)
    for (View& view : views)
      for (int k = 0; k < kFrames; ++k)
        view.time.add(
            time_frame([&] { view.renderer->render(camera, kWidth, kHeight, settings); }));
  const double n = double(state.iterations()) * kFrames;
  for (const View& view : views) {
    state.counters[std::string(view.name) + "_ms"] = 1e3 * view.time.wall / n;
    state.counters[std::string(view.name) + "_cpu_ms"] = 1e3 * view.time.cpu / n;
  }
  state.counters["sliders_vs_none"] = views[2].time.wall / views[0].time.wall;
  state.counters["sliders_vs_default"] = views[2].time.wall / views[1].time.wall;
  state.counters["sliders_vs_none_cpu"] = views[2].time.cpu / views[0].time.cpu;
}

}  // namespace

int main(int argc, char** argv) {
  register_scene("fig5_nine_lights", "fig5_nine_lights.toml");
  register_scene("fig6_bump", "fig6_bump.toml");
  register_scene("fig7_glass", "fig7_glass.toml");
  register_scene("fig8_room", "room.toml");
  register_scene("fig8_room_lamps", "room.toml+lamps");
  benchmark::RegisterBenchmark("converge/fig5_nine_lights",
                               [](benchmark::State& s) { converge(s, "fig5_nine_lights.toml"); })
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime()
      ->Iterations(1);
  benchmark::RegisterBenchmark("groups/fig8_room_lamps", light_groups_frame)
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime()
      ->Iterations(8);
  benchmark::RegisterBenchmark("lists/bundled", lists_bundled)
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime()
      ->Iterations(1);
  if (std::filesystem::exists(level_path())) {
    for (const bool above : {false, true}) {
      benchmark::RegisterBenchmark(above ? "level/above" : "level/inside",
                                   [above](benchmark::State& s) { level_frame(s, above); })
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime()
          ->Iterations(3);
    }
    for (const bool above : {false, true}) {
      benchmark::RegisterBenchmark(above ? "moving/above" : "moving/inside",
                                   [above](benchmark::State& s) { level_moving(s, above); })
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime()
          ->Iterations(1);  // each counter a mean over 12-frame sequences already
    }
    for (const bool above : {false, true}) {
      benchmark::RegisterBenchmark(above ? "detail/above" : "detail/inside",
                                   [above](benchmark::State& s) { level_detail(s, above); })
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime()
          ->Iterations(1);
    }
  }
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
