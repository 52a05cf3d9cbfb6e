// Viewer frame time on Mesa llvmpipe (OSMesa, no GPU) at 1024 x 768, for the paper's
// Figures 5, 6 and 8 (the default room) and Figure 7, against the yardstick of the same
// scene drawn with a flat shader (one colour per material, no lighting) in the same run.
// The ratio full/flat is the cost of the per-fragment direct light (exact polygon
// irradiance), the soft-shadow lookups and the maps.
//
//   build/bench/bench_viewer --benchmark_counters_tabular=true
// LP_NUM_THREADS sets llvmpipe's rasteriser threads (default: the core count).

#include <benchmark/benchmark.h>

#include <memory>
#include <string>

#include "bake/io/scene_load.h"
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

struct Fixture {
  lb::Renderer renderer;
  lb::ViewCamera camera;
  size_t triangles = 0;
  explicit Fixture(const std::string& file)
      : renderer((context(), lb::default_shader_directory())) {
    const lb::Scene scene =
        lb::load_scene(std::string(LIGHTBAKE_SOURCE_DIR) + "/scenes/" + file).scene;
    renderer.set_scene(scene, nullptr);
    camera = lb::choose_camera(scene, "");
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

void frame(benchmark::State& state, const std::string& file, bool flat) {
  Fixture& f = fixture(file);
  lb::RenderSettings settings;
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
  benchmark::RegisterBenchmark(("frame_flat/" + label).c_str(),
                               [file](benchmark::State& s) { frame(s, file, true); })
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime()  // the work is llvmpipe's threads, not this one's CPU time
      ->MinTime(1.0);
  benchmark::RegisterBenchmark(("frame_full/" + label).c_str(),
                               [file](benchmark::State& s) { frame(s, file, false); })
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime()
      ->MinTime(1.0);
}

}  // namespace

int main(int argc, char** argv) {
  register_scene("fig5_nine_lights", "fig5_nine_lights.toml");
  register_scene("fig6_bump", "fig6_bump.toml");
  register_scene("fig7_glass", "fig7_glass.toml");
  register_scene("fig8_room", "room.toml");
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
