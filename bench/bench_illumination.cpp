// Pass 1 speed: illumination ray casts per second beside raw Embree on the same scene, in the
// same run (the ratio is the number to watch, aim >= 0.7), time against ray density and map
// resolution, and the share of the pass spent on feelers.
#include <benchmark/benchmark.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "bake/accel.h"
#include "bake/illumination/atlas.h"
#include "bake/illumination/illumination.h"
#include "bake/io/scene_load.h"
#include "bake/lights.h"
#include "bake/sampling.h"
#include "test_helpers.h"

namespace lb {
namespace {

// A 4 x 4 x 2.5 m room with a ceiling light, a glass ball on a table, a tilted mirror and a
// brushed metal plate: caustics from all three specular kinds.
Scene bench_scene() {
  Scene scene;
  const int white = test::add_material(scene, Material{});
  Material light;
  light.reflectance = vec3(0.0f);
  light.emission = vec3(20.0f);
  const int lamp = test::add_material(scene, light);
  Material glass;
  glass.kind = MaterialKind::glass;
  glass.reflectance = vec3(0.95f);
  const int clear = test::add_material(scene, glass);
  Material mirror;
  mirror.kind = MaterialKind::mirror;
  mirror.reflectance = vec3(0.9f);
  const int shiny = test::add_material(scene, mirror);
  Material brushed;
  brushed.kind = MaterialKind::glossy;
  brushed.reflectance = vec3(0.9f);
  brushed.roughness = 0.3f;
  const int metal = test::add_material(scene, brushed);
  scene.meshes.push_back(test::make_box({-2, -2, 0}, {2, 2, 2.5f}, white, true, "room"));
  scene.meshes.push_back(
      test::make_quad({-0.25f, -0.25f, 2.45f}, {0, 0.5f, 0}, {0.5f, 0, 0}, lamp, "light"));
  scene.meshes.push_back(
      test::make_box({-0.6f, -0.6f, 0}, {0.6f, 0.6f, 0.75f}, white, false, "table"));
  scene.meshes.push_back(test::make_sphere({0, 0, 0.95f}, 0.2f, 48, 96, clear, false, "ball"));
  scene.meshes.push_back(
      test::make_quad({1.2f, -1, 0.3f}, {0, 2, 0}, {0.6f, 0, 0.8f}, shiny, "mirror"));
  scene.meshes.push_back(
      test::make_quad({-1.9f, -0.5f, 0.5f}, {0, 1, 0}, {0.3f, 0, 1.0f}, metal, "plate"));
  return scene;
}

double now_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// Bare rtcIntersect1 on all threads over the given rays.
double raw_embree_seconds(const Accel& accel, const std::vector<Ray>& rays) {
  const double start = now_seconds();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, rays.size(), 4096), [&](const auto& r) {
    benchmark::DoNotOptimize(accel.intersect_raw(rays.data() + r.begin(), r.size()));
  });
  return now_seconds() - start;
}

// Bare rtcIntersect1M (coherent: packets) on all threads over the given rays, in the pass's
// order: the yardstick for the packet API the pass itself uses.
double raw_stream_seconds(const Accel& accel, const std::vector<Ray>& rays) {
  const double start = now_seconds();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, rays.size(), 4096), [&](const auto& r) {
    benchmark::DoNotOptimize(accel.intersect_raw_many(rays.data() + r.begin(), r.size(), true));
  });
  return now_seconds() - start;
}

// As many rays as the pass cast, leaving the light's centre cosine-distributed: coherent
// primaries, the easy case for Embree.
std::vector<Ray> primary_rays(const Scene& scene, size_t count) {
  const AreaLight light = collect_lights(scene).at(0);
  const Frame frame(light.normal);
  std::vector<Ray> rays(count);
  Rng rng(5);
  for (Ray& ray : rays) {
    ray.direction = frame.to_world(square_to_cosine_hemisphere(rng.next_2d()));
    ray.origin = offset_ray_origin(light.centroid, light.normal, ray.direction);
  }
  return rays;
}

// LIGHTBAKE_BENCH_DUMP=dir writes the bench scene's atlas as a PFM (linear, bottom row first)
// so the map can be looked at: oiiotool map.pfm --mulc 4 --colorconvert linear sRGB -o map.png
void dump_map(const IlluminationMaps& maps, const char* name) {
  const char* dir = std::getenv("LIGHTBAKE_BENCH_DUMP");
  if (!dir || maps.width == 0) return;
  const std::string path = std::string(dir) + "/" + name + ".pfm";
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return;
  std::fprintf(f, "PF\n%d %d\n-1.0\n", maps.width, maps.height);
  std::fwrite(maps.radiance.data(), sizeof(vec3), maps.radiance.size(), f);
  std::fclose(f);
}

void BM_IlluminationVsRawEmbree(benchmark::State& state) {
  const Scene scene = bench_scene();
  const Accel accel(scene);
  IlluminationParams params;
  params.rays_per_zone_side = int(state.range(0));
  // The rays the pass casts, recorded once by a second (untimed) run: same seed, same rays.
  std::vector<Ray> cast;
  IlluminationParams logged = params;
  logged.cast_log = &cast;
  trace_illumination(scene, accel, logged);
  double pass = 0, tracing = 0, raw_same = 0, raw_stream = 0, raw_primary = 0, feelers = 0;
  uint64_t casts = 0, dense_casts = 0;
  IlluminationStats stats;
  for (auto _ : state) {
    const IlluminationMaps maps = trace_illumination(scene, accel, params);
    dump_map(maps, "bench_scene_map");
    stats = maps.stats;
    pass += stats.seconds;
    tracing += stats.seconds - stats.atlas_seconds;
    feelers += stats.feeler_seconds;
    casts += stats.ray_casts;
    dense_casts += cast.size();
    raw_same += raw_embree_seconds(accel, cast);
    raw_stream += raw_stream_seconds(accel, cast);
    raw_primary += raw_embree_seconds(accel, primary_rays(scene, stats.ray_casts));
  }
  // Pass casts per second (feelers + dense, whole pass or without the atlas) against bare
  // Embree on the very rays the dense pass cast (one rtcIntersect1 per ray, and the packet
  // API the pass uses, rtcIntersect1M coherent), and on as many random primaries.
  const double pass_rate = double(casts) / pass, tracing_rate = double(casts) / tracing;
  const double raw_same_rate = double(dense_casts) / raw_same;
  const double raw_stream_rate = double(dense_casts) / raw_stream;
  state.counters["pass_Mcasts_per_s"] = pass_rate * 1e-6;
  state.counters["raw_same_rays_Mcasts_per_s"] = raw_same_rate * 1e-6;
  state.counters["raw_stream_Mcasts_per_s"] = raw_stream_rate * 1e-6;
  state.counters["raw_primaries_Mcasts_per_s"] = double(casts) / raw_primary * 1e-6;
  state.counters["ratio_pass"] = pass_rate / raw_same_rate;
  state.counters["ratio_tracing"] = tracing_rate / raw_same_rate;
  state.counters["ratio_pass_vs_stream"] = pass_rate / raw_stream_rate;
  state.counters["ratio_tracing_vs_stream"] = tracing_rate / raw_stream_rate;
  state.counters["atlas_fraction"] = 1.0 - tracing / pass;
  state.counters["feeler_fraction"] = feelers / pass;
  state.counters["zones_traced"] = double(stats.zones_traced);
  state.counters["rays_saved"] = double(stats.rays_saved);
}
BENCHMARK(BM_IlluminationVsRawEmbree)
    ->Arg(64)
    ->Arg(256)
    ->Arg(512)  // the default density
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

void BM_TimeVsRayDensity(benchmark::State& state) {
  const Scene scene = bench_scene();
  const Accel accel(scene);
  IlluminationParams params;
  params.rays_per_zone_side = int(state.range(0));
  IlluminationStats stats;
  for (auto _ : state) stats = trace_illumination(scene, accel, params).stats;
  state.counters["illumination_rays"] = double(stats.illumination_rays);
  state.counters["feeler_fraction"] = stats.feeler_seconds / stats.seconds;
}
BENCHMARK(BM_TimeVsRayDensity)
    ->RangeMultiplier(2)
    ->Range(16, 256)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

void BM_TimeVsMapResolution(benchmark::State& state) {
  const Scene scene = bench_scene();
  const Accel accel(scene);
  IlluminationParams params;
  params.texel_size = float(state.range(0)) * 1e-3f;  // millimetres
  int width = 0, height = 0;
  for (auto _ : state) {
    const IlluminationMaps maps = trace_illumination(scene, accel, params);
    width = maps.width, height = maps.height;
  }
  state.counters["atlas_width"] = width;
  state.counters["atlas_height"] = height;
}
BENCHMARK(BM_TimeVsMapResolution)
    ->Arg(40)
    ->Arg(20)
    ->Arg(10)
    ->Arg(5)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The atlas alone (the pass's fixed cost): charts, packing, exact node areas, for the bench
// scene's receivers (room and table) at a texel size in millimetres.
void BM_AtlasBuild(benchmark::State& state) {
  const Scene scene = bench_scene();
  std::vector<bool> include(scene.meshes.size(), false);
  include[0] = include[2] = true;
  AtlasParams params;
  params.texel_size = float(state.range(0)) * 1e-3f;
  size_t nodes = 0;
  for (auto _ : state) nodes = build_atlas(scene, include, params).texel_area.size();
  state.counters["nodes"] = double(nodes);
}
BENCHMARK(BM_AtlasBuild)->Arg(24)->Arg(10)->Unit(benchmark::kMillisecond)->UseRealTime();

// The paper's scenes as H1 wrote them (scenes/*.toml), when present: the whole pass at
// default settings.
void BM_SceneFile(benchmark::State& state, const std::string& name) {
  Scene scene;
  try {
    scene = load_scene(std::string(LIGHTBAKE_SOURCE_DIR) + "/scenes/" + name + ".toml").scene;
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return;
  }
  const Accel accel(scene);
  IlluminationParams params;
  params.rays_per_zone_side = int(state.range(0));
  IlluminationStats stats;
  for (auto _ : state) {
    const IlluminationMaps maps = trace_illumination(scene, accel, params);
    dump_map(maps, (name + "_" + std::to_string(state.range(0))).c_str());
    stats = maps.stats;
  }
  state.counters["zones_traced"] = double(stats.zones_traced);
  state.counters["zones_total"] = double(stats.zones_total);
  state.counters["rays_saved"] = double(stats.rays_saved);
  state.counters["ray_casts"] = double(stats.ray_casts);
  state.counters["feeler_fraction"] = stats.feeler_seconds / stats.seconds;
  state.counters["atlas_fraction"] = stats.atlas_seconds / stats.seconds;
  state.counters["illumination_rays"] = double(stats.illumination_rays);
}
BENCHMARK_CAPTURE(BM_SceneFile, fig8_room, std::string("room"))
    ->Arg(64)
    ->Arg(512)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_SceneFile, fig3_ring, std::string("fig3_ring"))
    ->Arg(64)
    ->Arg(512)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_SceneFile, fig4_plates, std::string("fig4_plates"))
    ->Arg(64)
    ->Arg(512)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_SceneFile, fig7_glass, std::string("fig7_glass"))
    ->Arg(64)
    ->Arg(512)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace lb

BENCHMARK_MAIN();
