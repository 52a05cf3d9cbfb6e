// The HQ renderer's speed: (1) render time against the number of lights at equal spp (the
// one-shadow-ray method keeps direct light's cost flat: aim 100 lights <= 1.3x one light);
// (2) viewing + shadow rays per second beside bare Embree loops (Accel::intersect_raw and the
// stream API's intersect_raw_many) over the same number of camera rays in the same scene, same
// threads, same run (aim >= 0.7 of intersect_raw).
// The scenes: tests/hq/hq_scenes.cpp's room with a per_side x per_side grid of ceiling lights
// (1, 9 = Figure 5's arrangement, 100), same total power, a table casting shadows.

#include <benchmark/benchmark.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <memory>
#include <numeric>
#include <vector>

#include "bake/hq/hq_render.h"
#include "bake/surface.h"
#include "bake/thin_lens_camera.h"
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
    double cpu = 0.0;
    return render_seconds(stats, cpu);
  }
  // Wall seconds; `cpu` gets the process's CPU seconds (all threads) of the same render, which
  // other jobs on a shared machine disturb much less.
  double render_seconds(HqStats& stats, double& cpu) const {
    const double cpu_start = process_cpu_seconds();
    const auto start = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(renderer->render(scene.cameras[0], 1, stats));
    cpu = process_cpu_seconds() - cpu_start;
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  static double process_cpu_seconds() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
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
  const Fixture* fixtures[3] = {&one, &nine, &hundred};
  double best[3] = {1e30, 1e30, 1e30}, best_cpu[3] = {1e30, 1e30, 1e30};
  for (auto _ : state) {
    for (int repeat = 0; repeat < 3; ++repeat)
      for (int f = 0; f < 3; ++f) {
        HqStats stats;
        double cpu = 0.0;
        best[f] = std::min(best[f], fixtures[f]->render_seconds(stats, cpu));
        best_cpu[f] = std::min(best_cpu[f], cpu);
      }
  }
  state.counters["s_1_light"] = best[0];
  state.counters["s_9_lights"] = best[1];
  state.counters["s_100_lights"] = best[2];
  state.counters["ratio_9_to_1"] = best[1] / best[0];
  state.counters["ratio_100_to_1"] = best[2] / best[0];
  // The same in CPU seconds of the process (user + system, both threads).
  state.counters["cpu_ratio_9_to_1"] = best_cpu[1] / best_cpu[0];
  state.counters["cpu_ratio_100_to_1"] = best_cpu[2] / best_cpu[0];
}
BENCHMARK(BM_LightCountRatios)
    ->ArgsProduct({{0, 128}, {1, 0}})
    ->ArgNames({"sphere_rings", "reuse_choice"})
    ->Iterations(1)
    ->Unit(benchmark::kSecond)
    ->UseRealTime();

// Seconds for `trace(rays, count)` over all rays, split in blocks of 4096 over TBB.
template <typename Trace>
double raw_embree_seconds(const std::vector<Ray>& rays, const Trace& trace) {
  const auto start = std::chrono::steady_clock::now();
  const size_t hits = tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, rays.size(), 4096), size_t(0),
      [&](const tbb::blocked_range<size_t>& r, size_t acc) {
        return acc + trace(rays.data() + r.begin(), r.size());
      },
      [](size_t a, size_t b) { return a + b; });
  benchmark::DoNotOptimize(hits);
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Rays per second of the renderer (viewing + shadow, all work included) against two bare
// Embree loops over as many camera rays of the same view (16 jittered per pixel, in pixel
// order), split the same way over TBB: one rtcIntersect1 per ray (`ratio`) and the stream API,
// rtcIntersect1M with the coherent flag (`ratio_vs_stream`).
void BM_RaysVersusRawEmbree(benchmark::State& state) {
  const Fixture fixture(3, int(state.range(0)));
  const ThinLensCamera camera(fixture.scene.cameras[0], kWidth, kHeight);
  double best_hq = 0.0, best_raw = 0.0, best_stream = 0.0;
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
      const Accel& accel = fixture.renderer->accel();
      const double raw_seconds = raw_embree_seconds(
          raw, [&](const Ray* r, size_t n) { return accel.intersect_raw(r, n); });
      const double stream_seconds = raw_embree_seconds(raw, [&](const Ray* r, size_t n) {
        return accel.intersect_raw_many(r, n, /*coherent=*/true);
      });
      best_hq = std::max(best_hq, double(rays) / hq_seconds);
      best_raw = std::max(best_raw, double(rays) / raw_seconds);
      best_stream = std::max(best_stream, double(rays) / stream_seconds);
    }
  }
  state.counters["hq_Mrays_per_s"] = best_hq * 1e-6;
  state.counters["raw_Mrays_per_s"] = best_raw * 1e-6;
  state.counters["raw_stream_Mrays_per_s"] = best_stream * 1e-6;
  state.counters["ratio"] = best_hq / best_raw;
  state.counters["ratio_vs_stream"] = best_hq / best_stream;
}
BENCHMARK(BM_RaysVersusRawEmbree)
    ->Arg(0)
    ->Arg(128)
    ->ArgName("sphere_rings")
    ->Iterations(1)
    ->Unit(benchmark::kSecond)
    ->UseRealTime();

// Which order and Embree flag the renderer's shadow waves should use: the shadow rays of the
// view's primary hits (16 per pixel, one light chosen per hit as the renderer chooses it), in
// 1024-ray waves of 64 pixels in tile order, traced through occluded_many (a) in path order with
// the coherent flag, (b) in path order, incoherent, (c) sorted by light within the wave,
// coherent. Single thread, interleaved, best of 5: ns per shadow ray.
void BM_ShadowWaveOrder(benchmark::State& state) {
  const Fixture fixture(int(state.range(0)), int(state.range(1)));
  const HqRenderer& renderer = *fixture.renderer;
  const ThinLensCamera camera(fixture.scene.cameras[0], kWidth, kHeight);
  constexpr int kTile = 16, kWave = 1024;
  std::vector<Ray> rays;
  std::vector<int> light;
  Rng rng(7);
  for (int ty = 0; ty < kHeight; ty += kTile)
    for (int tx = 0; tx < kWidth; tx += kTile)
      for (int y = ty; y < ty + kTile; ++y)
        for (int x = tx; x < tx + kTile; ++x)
          for (int s = 0; s < 16; ++s) {
            const Ray primary =
                camera.generate(vec2(float(x), float(y)) + rng.next_2d(), {0.5f, 0.5f});
            const std::optional<Hit> hit = renderer.accel().intersect(primary);
            if (!hit) continue;
            const SurfacePoint sp = surface_at(fixture.scene, *hit, primary);
            const float side =
                glm::dot(primary.direction, sp.geometric_normal) < 0.0f ? 1.0f : -1.0f;
            ReceiverPoint receiver;
            receiver.position = sp.position;
            receiver.geometric_normal = side * sp.geometric_normal;
            receiver.shading_normal = side * sp.shading_normal;
            Ray ray;
            const DeferredEstimate e = renderer.direct_light().sample_one_light(
                receiver, rng.next_float(), rng.next_2d(), ray);
            if (!e.shadow_ray) continue;
            rays.push_back(ray);
            light.push_back(e.light);
          }
  std::vector<Ray> sorted(rays.size());
  for (size_t first = 0; first < rays.size(); first += kWave) {
    const size_t last = std::min(rays.size(), first + kWave);
    std::vector<size_t> order(last - first);
    std::iota(order.begin(), order.end(), first);
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return light[a] < light[b]; });
    for (size_t k = 0; k < order.size(); ++k) sorted[first + k] = rays[order[k]];
  }
  std::unique_ptr<bool[]> blocked(new bool[kWave]);
  auto seconds = [&](const std::vector<Ray>& wave_rays, bool coherent) {
    const auto start = std::chrono::steady_clock::now();
    for (size_t first = 0; first < wave_rays.size(); first += kWave)
      renderer.accel().occluded_many(wave_rays.data() + first,
                                     std::min<size_t>(kWave, wave_rays.size() - first),
                                     blocked.get(), coherent);
    benchmark::DoNotOptimize(blocked[0]);
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  double best[3] = {1e30, 1e30, 1e30};
  for (auto _ : state)
    for (int repeat = 0; repeat < 5; ++repeat) {
      best[0] = std::min(best[0], seconds(rays, true));
      best[1] = std::min(best[1], seconds(rays, false));
      best[2] = std::min(best[2], seconds(sorted, true));
    }
  const double per_ray = 1e9 / double(std::max<size_t>(rays.size(), 1));
  state.counters["ns_path_order_coherent"] = best[0] * per_ray;
  state.counters["ns_path_order_incoherent"] = best[1] * per_ray;
  state.counters["ns_by_light_coherent"] = best[2] * per_ray;
  state.counters["shadow_rays"] = double(rays.size());
}
BENCHMARK(BM_ShadowWaveOrder)
    ->ArgsProduct({{1, 3, 10}, {0, 128}})
    ->ArgNames({"per_side", "sphere_rings"})
    ->Iterations(1)
    ->Unit(benchmark::kSecond)
    ->UseRealTime();

}  // namespace
}  // namespace lb

BENCHMARK_MAIN();
