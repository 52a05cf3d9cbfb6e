// The HQ renderer's speed: (1) render time against the number of lights at equal spp (the
// one-shadow-ray method keeps direct light's cost flat: aim 100 lights <= 1.3x one light);
// (2) viewing + shadow rays per second beside a bare Embree loop (Accel::intersect_raw) over the
// same number of camera rays in the same scene, same threads, same run (aim >= 0.7).
// The scenes: tests/hq/hq_scenes.cpp's room with a per_side x per_side grid of ceiling lights
// (1, 9 = Figure 5's arrangement, 100), same total power, a table casting shadows.

#include <benchmark/benchmark.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <chrono>
#include <vector>

#include "bake/hq/camera.h"
#include "bake/hq/hq_render.h"
#include "hq_scenes.h"
#include "test_helpers.h"

namespace lb {
namespace {

constexpr int kWidth = 160;
constexpr int kHeight = 120;

struct Fixture {
  Scene scene;
  BakedScene baked;
  std::unique_ptr<HqRenderer> renderer;
  // `sphere_rings` > 0 adds a diffuse sphere of 2 * rings^2 triangles on the table, so rays
  // cost what they cost in a real scene rather than in 26 triangles.
  Fixture(int per_side, int sphere_rings, bool reuse_light_choice = true)
      : scene(test::make_light_grid_room(per_side)) {
    if (sphere_rings > 0)
      scene.meshes.push_back(test::make_sphere({0.3f, 1.5f, 0.0f}, 0.5f, sphere_rings,
                                               2 * sphere_rings, /*material: table*/ 2, false,
                                               "sphere"));
    baked = test::unbaked(scene);
    HqParams params;
    params.width = kWidth;
    params.height = kHeight;
    params.samples_per_side = 4;  // 16 spp
    params.reuse_light_choice = reuse_light_choice;
    renderer = std::make_unique<HqRenderer>(baked, params);
  }
  double render_seconds(HqStats& stats) const {
    const auto start = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(renderer->render(scene.cameras[0], 1, stats));
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
};

void BM_RenderByLightCount(benchmark::State& state) {
  const Fixture fixture(int(state.range(0)), int(state.range(1)));
  HqStats stats;
  for (auto _ : state) fixture.render_seconds(stats);
  state.counters["lights"] = double(fixture.renderer->direct_light().lights().size());
  state.counters["shadow_per_view"] = double(stats.rays.shadow) / double(stats.rays.viewing);
}
BENCHMARK(BM_RenderByLightCount)
    ->ArgsProduct({{1, 3, 10}, {0, 128}})
    ->ArgNames({"per_side", "sphere_rings"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The three light counts in one run, interleaved, best of 3: ratios to one light.
void BM_LightCountRatios(benchmark::State& state) {
  const int rings = int(state.range(0));
  const bool reuse = state.range(1) != 0;  // 0: the paper's Eq. 2 sweep at every hit
  const Fixture one(1, rings, reuse), nine(3, rings, reuse), hundred(10, rings, reuse);
  double best[3] = {1e30, 1e30, 1e30};
  for (auto _ : state) {
    for (int repeat = 0; repeat < 3; ++repeat) {
      HqStats stats;
      best[0] = std::min(best[0], one.render_seconds(stats));
      best[1] = std::min(best[1], nine.render_seconds(stats));
      best[2] = std::min(best[2], hundred.render_seconds(stats));
    }
  }
  state.counters["s_1_light"] = best[0];
  state.counters["s_9_lights"] = best[1];
  state.counters["s_100_lights"] = best[2];
  state.counters["ratio_9_to_1"] = best[1] / best[0];
  state.counters["ratio_100_to_1"] = best[2] / best[0];
}
BENCHMARK(BM_LightCountRatios)
    ->ArgsProduct({{0, 128}, {1, 0}})
    ->ArgNames({"sphere_rings", "reuse_choice"})
    ->Iterations(1)
    ->Unit(benchmark::kSecond)
    ->UseRealTime();

// Rays per second of the renderer (viewing + shadow, all work included) against bare
// rtcIntersect1 over as many camera rays of the same view, split the same way over TBB.
void BM_RaysVersusRawEmbree(benchmark::State& state) {
  const Fixture fixture(3, int(state.range(0)));
  const ThinLensCamera camera(fixture.scene.cameras[0], kWidth, kHeight);
  double best_hq = 0.0, best_raw = 0.0;
  for (auto _ : state) {
    for (int repeat = 0; repeat < 3; ++repeat) {
      HqStats stats;
      const double hq_seconds = fixture.render_seconds(stats);
      const uint64_t rays = stats.rays.viewing + stats.rays.shadow;
      std::vector<Ray> raw(rays);
      for (size_t i = 0; i < raw.size(); ++i) {
        const size_t pixel = (i / 16) % size_t(kWidth * kHeight);
        const float jx = float(i % 4) * 0.25f + 0.125f, jy = float((i / 4) % 4) * 0.25f + 0.125f;
        raw[i] =
            camera.generate({float(pixel % kWidth) + jx, float(pixel / kWidth) + jy}, {0.5f, 0.5f});
      }
      const auto start = std::chrono::steady_clock::now();
      const size_t hits = tbb::parallel_reduce(
          tbb::blocked_range<size_t>(0, raw.size(), 4096), size_t(0),
          [&](const tbb::blocked_range<size_t>& r, size_t acc) {
            return acc + fixture.renderer->accel().intersect_raw(raw.data() + r.begin(), r.size());
          },
          [](size_t a, size_t b) { return a + b; });
      const double raw_seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      benchmark::DoNotOptimize(hits);
      best_hq = std::max(best_hq, double(rays) / hq_seconds);
      best_raw = std::max(best_raw, double(rays) / raw_seconds);
    }
  }
  state.counters["hq_Mrays_per_s"] = best_hq * 1e-6;
  state.counters["raw_Mrays_per_s"] = best_raw * 1e-6;
  state.counters["ratio"] = best_hq / best_raw;
}
BENCHMARK(BM_RaysVersusRawEmbree)
    ->Arg(0)
    ->Arg(128)
    ->ArgName("sphere_rings")
    ->Iterations(1)
    ->Unit(benchmark::kSecond)
    ->UseRealTime();

}  // namespace
}  // namespace lb

BENCHMARK_MAIN();
