// Radiosity pass speed: rays per second of the whole pass next to bare Embree over the same
// refined scene, the same ray count and the same threads, measured in the same run; and how the
// pass time grows with the patch count. Yardsticks (each in blocks of 128 rays over TBB, as
// the pass):
//   raw     rtcIntersect1 (Accel::intersect_raw) over as many area-uniform patch rays (the
//           issue's original yardstick: random origins, so incoherent);
//   same    rtcIntersect1 over the very rays the pass cast (logged by an untimed second solve);
//   stream  rtcIntersect1M (Accel::intersect_raw_many) over those same rays in the pass's
//           order, incoherent as the pass traces them (and `stream_coherent`: with packets).
//
//   build/bench/bench_radiosity --benchmark_filter='BM_Throughput/budget:2000000'
//   build/bench/bench_radiosity --benchmark_filter=Throughput
//   build/bench/bench_radiosity --benchmark_filter=PatchCount
//   build/bench/bench_radiosity --benchmark_filter=Convergence64x   (the 64x check)

#include <benchmark/benchmark.h>
#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>

#include "bake/accel.h"
#include "bake/radiosity/radiosity.h"
#include "bake/sampling.h"
#include "scenes.h"
#include "test_helpers.h"

namespace lb {
namespace {

// CPU seconds of the whole process (all threads): robust to other load on a shared machine,
// where wall time is not.
double process_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

double total_area(const Scene& scene) {
  double area = 0.0;
  for (const Mesh& mesh : scene.meshes) area += mesh_area(mesh);
  return area;
}

// A point on the patch, uniform by area, and the refined triangle it lies on: u.x picks the
// triangle and is reused inside it (the pass does the same with its per-shot source table).
struct PatchSample {
  vec3 position;
  uint32_t triangle;
};
PatchSample sample_patch(const Patch& patch, const Mesh& refined, vec2 u) {
  const auto it = std::lower_bound(patch.triangle_cdf.begin(), patch.triangle_cdf.end(), u.x);
  const size_t index =
      std::min(size_t(it - patch.triangle_cdf.begin()), patch.triangles.size() - 1);
  const float lo = index == 0 ? 0.0f : patch.triangle_cdf[index - 1];
  const float hi = patch.triangle_cdf[index];
  const float ux = hi > lo ? std::clamp((u.x - lo) / (hi - lo), 0.0f, 0.99999994f) : 0.5f;
  const uint32_t t = patch.triangles[index];
  const uvec3 tri = refined.triangles[t];
  const vec2 b = square_to_triangle({ux, u.y});
  return {(1.0f - b.x - b.y) * refined.positions[tri.x] + b.x * refined.positions[tri.y] +
              b.y * refined.positions[tri.z],
          t};
}

// Rays like the pass's: area-uniform origins on patches, cosine-weighted directions.
std::vector<Ray> patch_rays(const Scene& traced, const Patches& patches, size_t count) {
  std::vector<Ray> rays(count);
  std::vector<double> cdf;
  double sum = 0.0;
  for (const Patch& p : patches.patches) cdf.push_back(sum += p.area);
  Rng rng(7);
  for (Ray& ray : rays) {
    const double x = double(rng.next_float()) * sum;
    const size_t index =
        std::min(size_t(std::lower_bound(cdf.begin(), cdf.end(), x) - cdf.begin()), cdf.size() - 1);
    const Patch& patch = patches.patches[index];
    const Mesh& mesh = traced.meshes[patch.mesh];
    const PatchSample s = sample_patch(patch, mesh, rng.next_2d());
    const vec3 n = triangle_normal(mesh, s.triangle);
    const vec3 d = Frame(n).to_world(square_to_cosine_hemisphere(rng.next_2d()));
    ray.origin = offset_ray_origin(s.position, n, d);
    ray.direction = d;
  }
  return rays;
}

// Same partitioning as the pass: blocks of 128 rays over TBB.
struct Seconds {
  double wall, cpu;
};
template <class TraceBlock>
Seconds yardstick_seconds(const std::vector<Ray>& rays, const TraceBlock& trace_block) {
  const auto start = std::chrono::steady_clock::now();
  const double cpu_start = process_cpu_seconds();
  constexpr size_t block = 128;
  const size_t blocks = (rays.size() + block - 1) / block;
  std::vector<size_t> hits(blocks);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, blocks, 1), [&](const auto& range) {
    for (size_t b = range.begin(); b != range.end(); ++b) {
      const size_t first = b * block, n = std::min(block, rays.size() - first);
      hits[b] = trace_block(rays.data() + first, n);
    }
  });
  benchmark::DoNotOptimize(hits.data());
  return {std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
          process_cpu_seconds() - cpu_start};
}
Seconds raw_seconds(const Accel& accel, const std::vector<Ray>& rays) {
  return yardstick_seconds(
      rays, [&](const Ray* first, size_t n) { return accel.intersect_raw(first, n); });
}
Seconds stream_seconds(const Accel& accel, const std::vector<Ray>& rays, bool coherent) {
  return yardstick_seconds(rays, [&](const Ray* first, size_t n) {
    return accel.intersect_raw_many(first, n, coherent);
  });
}

void run_pass(benchmark::State& state, const Scene& scene, const RadiosityParams& params) {
  const Accel accel(scene);
  double pass_rays = 0, pass_seconds = 0, setup = 0, pass_cpu = 0;
  Seconds raw{}, same{}, stream{}, stream_coherent{};
  size_t patch_count = 0;
  for (auto _ : state) {
    const double cpu_start = process_cpu_seconds();
    const VertexRadiosity result = solve_radiosity(scene, accel, params);
    pass_cpu = process_cpu_seconds() - cpu_start;
    const RadiosityStats& s = result.stats;
    pass_rays = double(s.ray_casts);
    pass_seconds = s.seconds - s.setup_seconds;
    setup = s.setup_seconds;
    patch_count = s.patch_count;
    state.SetIterationTime(s.seconds);

    // The yardsticks in the same run, on the refined scene the pass traced.
    state.PauseTiming();
    const Patches patches = build_patches(scene, params.patch_size, params.emitters_reflect);
    const Scene traced = refined_scene(scene, patches);
    const Accel traced_accel(traced);
    raw = raw_seconds(traced_accel, patch_rays(traced, patches, size_t(pass_rays)));
    std::vector<Ray> cast;
    RadiosityCallbacks logging;
    logging.cast_log = &cast;
    solve_radiosity(scene, accel, params, {}, logging);
    same = raw_seconds(traced_accel, cast);
    stream = stream_seconds(traced_accel, cast, false);
    stream_coherent = stream_seconds(traced_accel, cast, true);
    state.ResumeTiming();
  }
  const double pass_rate = pass_rays / pass_seconds;
  state.counters["patches"] = double(patch_count);
  state.counters["ray_casts"] = pass_rays;
  state.counters["setup_s"] = setup;
  state.counters["trace_s"] = pass_seconds;
  state.counters["pass_Mrays_s"] = pass_rate * 1e-6;
  state.counters["raw_Mrays_s"] = pass_rays / raw.wall * 1e-6;
  state.counters["same_Mrays_s"] = pass_rays / same.wall * 1e-6;
  state.counters["stream_Mrays_s"] = pass_rays / stream.wall * 1e-6;
  state.counters["stream_coherent_Mrays_s"] = pass_rays / stream_coherent.wall * 1e-6;
  // Pass rays/s over each yardstick's (wall time, pass without its setup).
  state.counters["ratio"] = pass_rate * raw.wall / pass_rays;
  state.counters["ratio_same"] = pass_rate * same.wall / pass_rays;
  state.counters["ratio_stream"] = pass_rate * stream.wall / pass_rays;
  state.counters["ratio_stream_coherent"] = pass_rate * stream_coherent.wall / pass_rays;
  // The same in CPU time (the pass's includes its setup): the work, without the machine's
  // other load.
  state.counters["cpu_ratio"] = raw.cpu / pass_cpu;
  state.counters["cpu_ratio_same"] = same.cpu / pass_cpu;
  state.counters["cpu_ratio_stream"] = stream.cpu / pass_cpu;
}

void BM_Throughput(benchmark::State& state) {
  const tbb::global_control threads(tbb::global_control::max_allowed_parallelism,
                                    size_t(state.range(1)));
  const Scene scene = test::make_room();
  RadiosityParams params;
  params.ray_budget = uint64_t(state.range(0));
  run_pass(state, scene, params);
}
BENCHMARK(BM_Throughput)
    ->ArgNames({"budget", "threads"})
    ->Args({2'000'000, 1})
    ->Args({2'000'000, 2})
    ->Args({8'000'000, 2})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

// The pass alone, no yardsticks: the target to profile with perf (docs/radiosity.md, Speed),
// and the pass's own rays/s at 1 and 2 threads.
void BM_PassOnly(benchmark::State& state) {
  const tbb::global_control threads(tbb::global_control::max_allowed_parallelism,
                                    size_t(state.range(1)));
  const Scene scene = test::make_room();
  const Accel accel(scene);
  RadiosityParams params;
  params.ray_budget = uint64_t(state.range(0));
  uint64_t casts = 0;
  for (auto _ : state) casts += solve_radiosity(scene, accel, params).stats.ray_casts;
  state.counters["Mrays_s"] = benchmark::Counter(double(casts) * 1e-6, benchmark::Counter::kIsRate);
}
BENCHMARK(BM_PassOnly)
    ->ArgNames({"budget", "threads"})
    ->Args({2'000'000, 1})
    ->Args({2'000'000, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The same on a heavier scene: the room with a finely tessellated diffuse ball (65k
// triangles, grouped into patches), where traversal, not the pass's bookkeeping, dominates.
void BM_ThroughputHeavy(benchmark::State& state) {
  Scene scene = test::make_room();
  Material ball;
  ball.reflectance = vec3(0.5f);
  scene.materials.push_back(ball);
  scene.meshes.push_back(test::make_sphere({2.9f, 0.6f, 2.9f}, 0.6f, 128, 256,
                                           int(scene.materials.size()) - 1, false, "ball"));
  RadiosityParams params;
  params.ray_budget = uint64_t(state.range(0));
  run_pass(state, scene, params);
}
BENCHMARK(BM_ThroughputHeavy)
    ->Arg(4'000'000)
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

// Pass time against patch count at a fixed budget of 4M rays.
void BM_PatchCount(benchmark::State& state) {
  const Scene scene = test::make_room();
  RadiosityParams params;
  params.ray_budget = 4'000'000;
  params.patch_size = float(std::sqrt(total_area(scene) / double(state.range(0))));
  run_pass(state, scene, params);
}
BENCHMARK(BM_PatchCount)
    ->Arg(1'000)
    ->Arg(10'000)
    ->Arg(100'000)
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

// The convergence check: default settings against 64x the rays.
void BM_Convergence64x(benchmark::State& state) {
  const Scene scene = test::make_room();
  const Accel accel(scene);
  const RadiosityParams defaults;
  RadiosityParams many = defaults;
  many.ray_budget *= 64;
  many.seed = 99;
  double error = 0.0;
  for (auto _ : state) {
    const VertexRadiosity a = solve_radiosity(scene, accel, defaults);
    const VertexRadiosity reference = solve_radiosity(scene, accel, many);
    error = mean_relative_error(a, reference);
  }
  state.counters["mean_relative_error"] = error;
}
BENCHMARK(BM_Convergence64x)->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace
}  // namespace lb

BENCHMARK_MAIN();
