// HQ mode at the edges of its settings: absurd sizes and sample counts are refused before any
// work, a huge sample count per pixel runs in bounded memory (a pixel's samples are traced in
// chunks) with the same bits on any thread count and the same mean as small passes, and a
// cancel stops a pass of one enormous tile within a wave.

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <tbb/global_control.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <thread>

#include "bake/hq/hq_render.h"
#include "bake/work_limits.h"
#include "hq_scenes.h"

namespace lb {
namespace {

HqParams tiny(int width, int height, int samples_per_side) {
  HqParams params;
  params.width = width;
  params.height = height;
  params.samples_per_side = samples_per_side;
  return params;
}

TEST(HqLimits, AbsurdSettingsAreRefusedByName) {
  auto message = [](const HqParams& params) {
    try {
      check_hq_params(params);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(message(tiny(0, 10, 1)).find("size 0x10"), std::string::npos);
  EXPECT_NE(message(tiny(20000, 10, 1)).find("[1, 16384]"), std::string::npos);
  EXPECT_NE(message(tiny(8, 8, 2000)).find("4000000 samples per pixel"), std::string::npos);
  EXPECT_EQ(message(tiny(4096, 4096, 1)), "") << "1 GB of film";
  EXPECT_EQ(message(tiny(8, 8, 1024)), "") << "2^20 samples per pixel is the cap itself";
}

uint64_t peak_rss_kib() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return uint64_t(usage.ru_maxrss);
}

// 48^2 = 2304 samples a pixel in chunks of 1000 paths: each pixel is traced in three chunks.
// Same bits on any thread count, and, in a scene without specular surfaces, the same bits as
// the whole pixel in one wave (the chunks draw the same numbers in the same order).
TEST(HqLimits, ChunkedPixelsGiveTheSameBits) {
  const Scene scene = test::make_light_grid_room(3);
  const BakedScene baked = test::unbaked(scene);
  HqParams params = tiny(6, 4, 48);
  params.max_wave_paths = 1000;
  const HqRenderer chunked(baked, params);
  auto render_with = [&](const HqRenderer& renderer, int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
    HqStats stats;
    return renderer.render(scene.cameras[0], 1, stats);
  };
  const std::vector<vec3> one = render_with(chunked, 1);
  const std::vector<vec3> two = render_with(chunked, 2);
  EXPECT_EQ(std::memcmp(one.data(), two.data(), one.size() * sizeof(vec3)), 0);
  params.max_wave_paths = 1 << 20;
  const std::vector<vec3> whole = render_with(HqRenderer(baked, params), 2);
  EXPECT_EQ(std::memcmp(one.data(), whole.data(), one.size() * sizeof(vec3)), 0);
  EXPECT_GT(one[5].x, 0.0f);
}

// One pixel at 512^2 samples: before chunking, a wave held 64 pixels' worth of paths
// (~7 GB here); now a few hundred KB a thread.
TEST(HqLimits, AQuarterMillionSamplesAPixelStayInBoundedMemory) {
  const Scene scene = test::make_light_grid_room(3);
  const BakedScene baked = test::unbaked(scene);
  const uint64_t before = peak_rss_kib();
  const HqRenderer renderer(baked, tiny(1, 1, 512));
  HqStats stats;
  const std::vector<vec3> image = renderer.render(scene.cameras[0], 1, stats);
  EXPECT_EQ(stats.rays.samples, 512u * 512u);
  EXPECT_GT(image[0].x, 0.0f);
  const uint64_t grown_kib = peak_rss_kib() - before;
  RecordProperty("peak_growth_kib", std::to_string(grown_kib));
  EXPECT_LT(grown_kib, 100u * 1024u) << "peak memory grew by " << grown_kib << " KiB";
}

// A 16 x 16 tile at 1024^2 samples a pixel would run for minutes; a cancel ends it in a wave.
TEST(HqLimits, CancelStopsInsideATile) {
  const Scene scene = test::make_light_grid_room(3);
  const BakedScene baked = test::unbaked(scene);
  const HqRenderer renderer(baked, tiny(16, 16, 1024));
  std::atomic<bool> cancel{false};
  Progress progress;
  progress.cancel = &cancel;
  std::thread stopper([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    cancel = true;
  });
  const auto start = std::chrono::steady_clock::now();
  HqStats stats;
  EXPECT_THROW(renderer.render(scene.cameras[0], 1, stats, progress), Cancelled);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  stopper.join();
  RecordProperty("seconds_to_stop", std::to_string(seconds));
  // The requirement is 1 s after the cancel; the bound leaves room for a loaded machine.
  EXPECT_LT(seconds, 3.0);
}

}  // namespace
}  // namespace lb
