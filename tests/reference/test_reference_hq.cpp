// The reference against HQ mode where HQ is exact (its direct term), and its determinism.

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstring>
#include <string>

#include "bake/hq/hq_render.h"
#include "bake/io/scene_load.h"
#include "bake/reference/reference.h"
#include "hq_scenes.h"
#include "reference_test_support.h"
#include "test_helpers.h"

namespace lb {
namespace {

using reference::Film;
using reference::grey;
using reference::ReferenceParams;
using reference::ReferenceRenderer;
using reference::ReferenceStats;

Scene bundled(const std::string& name) {
  return load_scene(test::source_dir() + "/scenes/" + name).scene;
}

// Direct light alone on a bundled scene: the room (a light, diffuse walls, a block, a glass
// ball) and Figure 6 (textures and bump maps: the same reflectance and bump model). HQ mode with
// only its direct term (HqParams direct, no map, no radiosity) estimates the paths E S* L and E S*
// D L with one shadow ray per diffuse hit, the reference with terms = direct estimates the same
// paths with next-event estimation and MIS. Two unbiased estimators of one image: they agree over
// the image and per region within their noise.
class ReferenceAgainstHq : public testing::TestWithParam<const char*> {};

TEST_P(ReferenceAgainstHq, DirectLightAgrees) {
  const Scene scene = bundled(GetParam());
  const Camera& camera = scene.cameras.at(0);
  constexpr int width = 48, height = 36;

  HqParams hq;
  hq.width = width;
  hq.height = height;
  hq.samples_per_side = 8;  // 64 spp a pass
  hq.direct = true;
  hq.illumination_map = false;
  hq.radiosity = false;
  const BakedScene baked = test::unbaked(scene);
  const HqRenderer hq_renderer(baked, hq);
  HqStats hq_stats;
  const std::vector<vec3> a = hq_renderer.render(camera, 8, hq_stats);  // 512 spp

  ReferenceParams params;
  params.width = width;
  params.height = height;
  params.spp = 512;
  params.terms = reference::Terms::direct;
  const Accel accel(scene);
  const ReferenceRenderer renderer(scene, accel, camera, params);
  ReferenceStats stats;
  const Film film = renderer.render(stats);
  const std::vector<vec3> b = film.average();

  // The whole image, and 6 x 6 pixel blocks (each block's mean is much less noisy than a pixel).
  double sum_a = 0.0, sum_b = 0.0;
  for (size_t i = 0; i < a.size(); ++i) sum_a += grey(a[i]), sum_b += grey(b[i]);
  double worst_block = 0.0;
  for (int by = 0; by < height; by += 6)
    for (int bx = 0; bx < width; bx += 6) {
      double block_a = 0.0, block_b = 0.0;
      for (int y = by; y < by + 6; ++y)
        for (int x = bx; x < bx + 6; ++x) {
          block_a += grey(a[size_t(y * width + x)]);
          block_b += grey(b[size_t(y * width + x)]);
        }
      if (block_a > 1e-3 * sum_a / 48.0)  // skip blocks that are (almost) black
        worst_block = std::max(worst_block, std::abs(block_b / block_a - 1.0));
    }
  const double se = film.noise().mean_relative_standard_error;
  // Measured (48 x 36, 512 spp each), room: image means 0.06% apart, worst 6 x 6 block 1.7%
  // apart, the reference's image-mean standard error 0.11% (HQ's is similar), so 0.6% is about
  // four combined standard errors; fig6_bump: 0.01% apart, worst block 1.8%, error 0.03%.
  EXPECT_NEAR(sum_b / sum_a, 1.0, 0.006) << "reference image mean standard error " << se;
  EXPECT_LT(worst_block, 0.05);
}

INSTANTIATE_TEST_SUITE_P(Scenes, ReferenceAgainstHq, testing::Values("room.toml", "fig6_bump.toml"),
                         [](const auto& info) {
                           const std::string name = info.param;
                           return name.substr(0, name.find('.'));
                         });

// Same seed and pass count: the same bits on one thread and on two (tiles and light blocks
// are fixed, splats are added in block order).
TEST(ReferenceDeterminism, OneAndTwoThreadsGiveTheSameBits) {
  const Scene scene = bundled("room.toml");
  ReferenceParams params;
  params.width = 40;
  params.height = 30;
  params.spp = 4;
  params.light_paths_per_pixel = 2.0;
  params.light_block_size = 256;  // many blocks, so threads interleave them
  const Accel accel(scene);
  const ReferenceRenderer renderer(scene, accel, scene.cameras.at(0), params);
  auto render_with = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
    ReferenceStats stats;
    return renderer.render(stats);
  };
  const Film one = render_with(1), two = render_with(2);
  for (int h = 0; h < 2; ++h) {
    ASSERT_EQ(one.half[h].size(), two.half[h].size());
    EXPECT_EQ(std::memcmp(one.half[h].data(), two.half[h].data(),
                          one.half[h].size() * sizeof(glm::dvec3)),
              0)
        << "half " << h;
  }
  // And a different seed gives a different image (the test can fail).
  ReferenceParams other = params;
  other.seed = 2;
  const ReferenceRenderer reseeded(scene, accel, scene.cameras.at(0), other);
  ReferenceStats stats;
  const Film different = reseeded.render(stats);
  EXPECT_NE(std::memcmp(one.half[0].data(), different.half[0].data(),
                        one.half[0].size() * sizeof(glm::dvec3)),
            0);
}

}  // namespace
}  // namespace lb
