// The radiosity pass at the edges of its settings: absurd budgets and patch sizes are refused
// by name before any work, and a shot of billions of rays runs in bounded memory and stops
// within a chunk when cancelled (it used to hold every deposit of the shot and ignore Ctrl-C).

#include <gtest/gtest.h>
#include <sys/resource.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <thread>

#include "bake/accel.h"
#include "bake/radiosity/radiosity.h"
#include "bake/work_limits.h"
#include "scenes.h"

namespace lb {
namespace {

std::string refusal(const Scene& scene, const RadiosityParams& params) {
  try {
    check_radiosity_params(scene, params);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(RadiosityLimits, AbsurdSettingsAreRefusedByName) {
  const Scene scene = test::make_room();
  RadiosityParams params;
  EXPECT_EQ(refusal(scene, params), "");
  params.ray_budget = 1'000'000'000'000;
  EXPECT_NE(refusal(scene, params).find("ray_budget = 1000000000000 is outside"),
            std::string::npos);
  params = {};
  params.patch_size = 1e-9f;
  const std::string tiny = refusal(scene, params);
  EXPECT_NE(tiny.find("patch_size 1e-09 m gives about"), std::string::npos) << tiny;
  EXPECT_NE(tiny.find("over the cap"), std::string::npos) << tiny;
  params.patch_size = std::nanf("");
  EXPECT_NE(refusal(scene, params).find("patch_size"), std::string::npos);
  params = {};
  params.convergence = 2.0;
  EXPECT_NE(refusal(scene, params).find("convergence"), std::string::npos);
}

// The estimate that guards the patch count is close to what build_patches makes.
TEST(RadiosityLimits, PatchEstimateIsCloseToTheCount) {
  const Scene scene = test::make_room();
  for (float h : {0.0f, 0.5f, 0.2f}) {
    const double estimate = estimate_patch_count(scene, h, true);
    const double actual = double(build_patches(scene, h, true).patches.size());
    EXPECT_GT(estimate, 0.5 * actual) << "h " << h;
    EXPECT_LT(estimate, 2.0 * actual) << "h " << h;
  }
}

uint64_t peak_rss_kib() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return uint64_t(usage.ru_maxrss);
}

// The light's first shot alone is ~4e9 rays at this budget: a cancel after 300 ms must end it
// promptly, and memory must not have grown with the shot (a deposit list of every ray was
// ~56 bytes a ray).
TEST(RadiosityLimits, AHugeShotStopsOnCancelInBoundedMemory) {
  const Scene scene = test::make_room();
  const Accel accel(scene);
  RadiosityParams params;
  params.ray_budget = kMaxRadiosityRayBudget;
  std::atomic<bool> cancel{false};
  Progress progress;
  progress.cancel = &cancel;
  const uint64_t before = peak_rss_kib();
  std::thread stopper([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    cancel = true;
  });
  const auto start = std::chrono::steady_clock::now();
  EXPECT_THROW(solve_radiosity(scene, accel, params, progress), Cancelled);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  stopper.join();
  const uint64_t grown_kib = peak_rss_kib() - before;
  RecordProperty("seconds_to_stop", std::to_string(seconds));
  RecordProperty("peak_growth_kib", std::to_string(grown_kib));
  EXPECT_LT(seconds, 3.0) << "1 s is the requirement; the bound leaves room for a loaded machine";
  EXPECT_LT(grown_kib, 200u * 1024u);
}

}  // namespace
}  // namespace lb
