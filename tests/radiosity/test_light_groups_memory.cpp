// Light groups' memory (issue 39): a bake may grow by no more than the extra groups' maps and
// vertex radiance. The soft-light map is where the groups' working maps meet (each group's
// gather correction and its resampled base); its step's peak of allocated bytes, four groups
// against the same scene as one, may exceed the four groups' own soft-light maps (what the
// step returns beyond the whole map) by little. Counted by this executable's operator new on
// one thread, so the peak is the same in every run.

#include <gtest/gtest.h>
#include <malloc.h>
#include <tbb/global_control.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <new>
#include <string>

#include "bake/light_groups.h"
#include "bake/lightmap/soft_texels.h"
#include "bake/pipeline/bake.h"
#include "scenes.h"

namespace {

std::atomic<int64_t> g_live{0}, g_peak{0};

void* counted(size_t bytes) {
  void* p = std::malloc(bytes > 0 ? bytes : 1);
  if (!p) throw std::bad_alloc();
  const int64_t live = g_live += int64_t(malloc_usable_size(p));
  int64_t peak = g_peak.load();
  while (live > peak && !g_peak.compare_exchange_weak(peak, live)) {
  }
  return p;
}

void uncounted(void* p) {
  if (!p) return;
  g_live -= int64_t(malloc_usable_size(p));
  std::free(p);
}

}  // namespace

// Every form that frees with plain delete: the nothrow ones too (std::stable_sort's buffer),
// else the sanitizers see operator new's memory go to free.
void* operator new(size_t bytes) { return counted(bytes); }
void* operator new[](size_t bytes) { return counted(bytes); }
void* operator new(size_t bytes, const std::nothrow_t&) noexcept {
  try {
    return counted(bytes);
  } catch (const std::bad_alloc&) {
    return nullptr;
  }
}
void* operator new[](size_t bytes, const std::nothrow_t& tag) noexcept {
  return operator new(bytes, tag);
}
void operator delete(void* p) noexcept { uncounted(p); }
void operator delete[](void* p) noexcept { uncounted(p); }
void operator delete(void* p, size_t) noexcept { uncounted(p); }
void operator delete[](void* p, size_t) noexcept { uncounted(p); }

namespace lb {
namespace {

// The room with a mirror and a ball, its ceiling light and three point lamps each in a group
// of its own (`grouped`), or all in none.
Scene four_light_room(bool grouped) {
  Scene scene = test::make_room_with_mirror();
  for (Material& m : scene.materials)
    if (m.is_emitter()) m.light_group = grouped ? "ceiling" : "";
  const vec3 positions[3] = {{0.6f, 2.4f, 3.2f}, {3.4f, 2.4f, 0.6f}, {0.6f, 0.5f, 0.6f}};
  for (int k = 0; k < 3; ++k) {
    Lamp lamp;
    lamp.kind = LampKind::point;
    lamp.position = positions[k];
    lamp.intensity = vec3(20.0f / (4.0f * 3.14159265f));
    lamp.light_group = grouped ? "lamp" + std::to_string(k) : "";
    scene.lights.push_back(lamp);
  }
  return scene;
}

BakeParams params() {
  BakeParams p;
  p.illumination.rays_per_zone_side = 16;
  p.illumination.texel_size = 0.02f;  // 0.23 M texels: the maps decide the step's memory
  p.radiosity.ray_budget = 100'000;
  p.soft_texels.gather_rays = 0;  // the bake's own map: the plain resampling (time)
  p.soft_texels.points_side = 1;
  p.seed = 3;
  return p;
}

struct StepPeak {
  double extra_bytes = 0.0;  // the step's peak of allocated bytes beyond what it started with
  SoftTexelMap map;
};

StepPeak soft_step_peak(const Scene& scene, const BakeResult& bake, const BakeParams& p) {
  StepPeak out;
  const int64_t before = g_live.load();
  g_peak = before;
  SoftTexelParams soft = p.soft_texels;
  soft.gather_rays = 1;  // the gather and its correction: the step's largest working set
  out.map = soft_light_texels(scene, bake, soft);
  out.extra_bytes = double(g_peak.load() - before);
  return out;
}

TEST(LightGroupsMemory, SoftLightStepGrowsByTheGroupsMapsAlone) {
  tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
  const BakeParams p = params();
  const Scene grouped = four_light_room(true), plain = four_light_room(false);
  ASSERT_EQ(light_group_names(grouped).size(), 4u);
  ASSERT_TRUE(light_group_names(plain).empty());
  const BakeResult four = bake_scene(grouped, p), one = bake_scene(plain, p);
  ASSERT_EQ(four.illumination.radiance.size(), one.illumination.radiance.size());
  const StepPeak peak_four = soft_step_peak(grouped, four, p);
  const StepPeak peak_one = soft_step_peak(plain, one, p);
  ASSERT_EQ(peak_four.map.group_radiance.size(), 4u);
  const double map = double(one.illumination.radiance.size() * sizeof(vec3));
  const double growth = peak_four.extra_bytes - peak_one.extra_bytes;
  std::printf("soft-light step peak: one %.1f MiB, four %.1f MiB, growth %.2f maps of %.2f MiB "
              "(the groups' own: 4)\n",
              peak_one.extra_bytes / 1048576.0, peak_four.extra_bytes / 1048576.0,
              growth / map, map / 1048576.0);
  EXPECT_GT(map, 2e6);  // the maps, not the rest, decide the comparison
  // The four soft-light maps the groups return, and a quarter map for the gather's group
  // terms (a texel index, 4 B a texel, and the lit caustic texels).
  EXPECT_LE(growth, 4.25 * map);
  // The groups' maps are real: they add up to the whole map.
  double whole = 0.0, parts = 0.0;
  for (size_t k = 0; k < peak_four.map.radiance.size(); ++k) {
    whole += double(peak_four.map.radiance[k].y);
    for (const auto& layer : peak_four.map.group_radiance) parts += double(layer[k].y);
  }
  EXPECT_GT(whole, 0.0);
  EXPECT_NEAR(parts / whole, 1.0, 1e-5);
}

}  // namespace
}  // namespace lb
