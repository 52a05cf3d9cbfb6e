// A level far from its file's origin renders as it does at the origin: the loaders centre a
// far scene (recentre_far_scene), so ray offsets and intersections keep their precision. The
// room with two blocks, authored 1e4 m and 1e5 m out (its coordinates rounded to float there,
// as a loader would), is baked and rendered in HQ mode and compared with the same room at the
// origin. Before the centring, the 1e4 m room rendered ~2.7% brighter with shadow streaks and
// the 1e5 m room had acne everywhere.

#include <gtest/gtest.h>

#include <cmath>

#include "bake/hq/hq_render.h"
#include "bake/io/scene_load.h"
#include "bake/lights.h"
#include "bake/pipeline/bake.h"
#include "test_helpers.h"

namespace lb {
namespace {

double channel_sum(vec3 v) {
  return double(v.x) + v.y + v.z;
}

Scene moved(const Scene& scene, glm::dvec3 offset) {
  Scene out = scene;
  for (Mesh& mesh : out.meshes)
    for (vec3& p : mesh.positions) p = vec3(glm::dvec3(p) + offset);
  for (Camera& camera : out.cameras) {
    camera.position = vec3(glm::dvec3(camera.position) + offset);
    camera.target = vec3(glm::dvec3(camera.target) + offset);
  }
  return out;
}

std::vector<vec3> bake_and_render(const Scene& scene, uint64_t seed = 1) {
  BakeParams bake_params;
  bake_params.seed = seed;
  bake_params.radiosity.ray_budget = 400'000;
  const BakeResult bake = bake_scene(scene, bake_params);
  const BakedScene baked = make_baked_scene(scene, bake);
  HqParams params;
  params.width = 64;
  params.height = 48;
  params.samples_per_side = 4;
  const HqRenderer renderer(baked, params);
  HqStats stats;
  return renderer.render(baked.scene.cameras.at(0), 1, stats);
}

struct Difference {
  double mean_relative = 0.0;  // over pixels and channels, |a - b| / (b + 0.01 mean)
  double sum_ratio = 0.0;      // sum a / sum b
};

Difference difference(const std::vector<vec3>& a, const std::vector<vec3>& b) {
  double sum_a = 0.0, sum_b = 0.0;
  for (size_t i = 0; i < a.size(); ++i)
    sum_a += a[i].x + a[i].y + a[i].z, sum_b += b[i].x + b[i].y + b[i].z;
  const double epsilon = 0.01 * sum_b / double(3 * b.size());
  Difference d;
  for (size_t i = 0; i < a.size(); ++i)
    for (int c = 0; c < 3; ++c)
      d.mean_relative += std::abs(a[i][c] - b[i][c]) / (b[i][c] + epsilon);
  d.mean_relative /= double(3 * a.size());
  d.sum_ratio = sum_a / sum_b;
  return d;
}

TEST(FarFromOrigin, ALevelTenAndHundredKilometresOutRendersAsAtTheOrigin) {
  const LoadResult loaded = load_scene(test::source_dir() + "/scenes/room_two_blocks.toml");
  ASSERT_EQ(loaded.scene.world_origin, glm::dvec3(0.0)) << "a scene at the origin stays put";
  const std::vector<vec3> at_origin = bake_and_render(loaded.scene);

  // Another seed at the origin: how far noise alone moves the image.
  const Difference noise = difference(bake_and_render(loaded.scene, 2), at_origin);
  RecordProperty("noise_mean_relative", std::to_string(noise.mean_relative));
  RecordProperty("noise_sum_ratio", std::to_string(noise.sum_ratio));

  for (const double distance : {1e4, 1e5}) {
    Scene far = moved(loaded.scene, {distance, 0.0, distance});
    ASSERT_TRUE(recentre_far_scene(far));
    EXPECT_NEAR(far.world_origin.x, distance, 1.0);
    const Difference d = difference(bake_and_render(far), at_origin);
    const double power_ratio = channel_sum(total_power(collect_lights(far))) /
                               channel_sum(total_power(collect_lights(loaded.scene)));
    RecordProperty("power_ratio_" + std::to_string(int(distance)), std::to_string(power_ratio));
    RecordProperty("mean_relative_" + std::to_string(int(distance)),
                   std::to_string(d.mean_relative));
    RecordProperty("sum_ratio_" + std::to_string(int(distance)), std::to_string(d.sum_ratio));
    // At 1e5 m the file's own float coordinates are 8 mm apart: the geometry itself changes by
    // up to 4 mm (the light's power by -0.8%), which no renderer can undo; the image must follow
    // that change and nothing more, and differ per pixel no more than another seed does.
    // So the per-pixel bound is another seed's difference, plus at 1e5 m the geometry's own
    // change, which shows as about the power's. Measured with the default patches and
    // soft-light map of 3 Dec 2026 (another seed at the origin: 0.97%, 1.001): 1e4 m 0.86% and
    // 1.002; 1e5 m 1.26% and 0.993 for a power ratio of 0.992 (before, with the map's noisier
    // defaults: noise 1.73%, 1e4 m 1.73%, 1e5 m 2.01%). Without the centring (the coarser
    // patches of the time, noise 0.71%): 4.0% and 1.011 at 1e4 m, 15.6% and 0.958 at 1e5 m.
    EXPECT_NEAR(d.sum_ratio / power_ratio, 1.0, 0.005) << distance << " m";
    EXPECT_LT(d.mean_relative, 1.3 * noise.mean_relative + std::abs(1.0 - power_ratio))
        << distance << " m";
  }
}

}  // namespace
}  // namespace lb
