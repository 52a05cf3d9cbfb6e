// Issue 16: pass 1 splats into fixed-point sums, so its dense rays split into shards whose sums
// add, in any order and on any thread count, to the bits of the whole pass.

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numbers>
#include <vector>

#include "bake/accel.h"
#include "bake/illumination/fixed_sums.h"
#include "bake/illumination/illumination.h"
#include "bake/lights.h"
#include "test_helpers.h"

namespace lb {
namespace {

using illumination::FixedOverflow;
using illumination::FixedScale;
using illumination::Pass1Sums;

// A closed room lit by two lights through a mirror, a glass ball and a glossy plate: every
// kind of specular path, deposits on many charts.
Scene caustic_room() {
  Scene scene;
  Material light;
  light.reflectance = vec3(0.0f);
  light.emission = vec3(5.0f, 4.0f, 3.0f);
  Material shiny;
  shiny.kind = MaterialKind::mirror;
  shiny.reflectance = vec3(0.7f);
  Material clear;
  clear.kind = MaterialKind::glass;
  clear.reflectance = vec3(1.0f);
  clear.ior = 1.5f;
  Material brushed;
  brushed.kind = MaterialKind::glossy;
  brushed.reflectance = vec3(0.9f);
  brushed.roughness = 0.4f;
  const int white = test::add_material(scene, Material{}), lamp = test::add_material(scene, light);
  scene.meshes.push_back(test::make_box({-2, -2, 0}, {2, 2, 2.5f}, white, true, "room"));
  scene.meshes.push_back(
      test::make_quad({-1.2f, -0.2f, 2.45f}, {0, 0.4f, 0}, {0.4f, 0, 0}, lamp, "l1"));
  scene.meshes.push_back(
      test::make_quad({0.8f, -0.2f, 2.45f}, {0, 0.4f, 0}, {0.4f, 0, 0}, lamp, "l2"));
  scene.meshes.push_back(test::make_quad({-1, -1, 0.01f}, {1.5f, 0, 0}, {0, 1.5f, 0.5f},
                                         test::add_material(scene, shiny), "mirror"));
  scene.meshes.push_back(test::make_sphere({0.8f, 0.8f, 0.6f}, 0.3f, 16, 32,
                                           test::add_material(scene, clear), false, "ball"));
  scene.meshes.push_back(test::make_quad({1.9f, -1, 0.5f}, {0, 2, 0}, {-0.3f, 0, 1},
                                         test::add_material(scene, brushed), "plate"));
  return scene;
}

bool same_tally(const illumination::FixedTally& a, const illumination::FixedTally& b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

TEST(Pass1Shards, FourShardsOnAnyThreadCountAddToTheBitsOfTheWholePass) {
  Scene scene = caustic_room();
  for (Mesh& mesh : scene.meshes) mesh.bake.caustic_origins = CausticOrigins::over_light;
  const Accel accel(scene);
  IlluminationParams params;
  params.rays_per_zone_side = 48;  // 2 lights x 36 zones x 48^2 = 166k rays, 41 batches
  params.trace_all_zones = true;
  const IlluminationPass pass(scene, accel, params);
  ASSERT_GT(pass.atlas_width(), 0);
  ASSERT_GE(pass.batch_count(), 16u);

  Pass1Sums whole = pass.empty_sums();
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    pass.trace(whole, 0, 1);
  }
  std::vector<Pass1Sums> shards;
  for (int i = 0; i < 4; ++i) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(1 + i % 2));
    shards.push_back(pass.empty_sums());
    pass.trace(shards.back(), i, 4);
  }
  // Balanced by rays to one batch (at most 8191 rays); every shard got work.
  const uint64_t quarter = pass.planned_rays() / 4;
  for (const Pass1Sums& s : shards) {
    EXPECT_GT(s.tally.rays, 0u);
    EXPECT_LE(std::max(s.tally.rays, quarter) - std::min(s.tally.rays, quarter), 8191u)
        << s.tally.rays << " rays against a quarter of " << pass.planned_rays();
  }
  Pass1Sums total = pass.empty_sums();
  for (int i : {3, 1, 0, 2}) total.add(shards[size_t(i)]);
  EXPECT_EQ(total.tally.rays, pass.planned_rays());
  EXPECT_TRUE(total.node_power == whole.node_power);
  EXPECT_TRUE(total.node_weight == whole.node_weight);
  EXPECT_TRUE(same_tally(total.tally, whole.tally));

  // The maps too, and trace_illumination's (all threads) are the same.
  const IlluminationMaps merged = pass.finish(total),
                         one = trace_illumination(scene, accel, params);
  EXPECT_TRUE(test::same_bits(merged.radiance, pass.finish(whole).radiance));
  EXPECT_TRUE(test::same_bits(merged.radiance, one.radiance));
  EXPECT_EQ(merged.stats.power_deposited, one.stats.power_deposited);
  EXPECT_EQ(merged.stats.ray_casts, one.stats.ray_casts);

  // Energy of the merged pass: every path ends in one of four ways (1e-5; measured 1.5e-8),
  // nothing leaves the closed room, and the map holds the deposited power (1e-4; measured
  // 3.1e-8). Shards measured 42768, 41040, 41040, 41040 rays of 165888.
  const IlluminationStats& s = merged.stats;
  const vec3 emitted = total_power(collect_lights(scene));
  double mapped = 0.0;
  for (size_t k = 0; k < merged.radiance.size(); ++k)
    if (merged.valid[k])
      mapped += double(merged.radiance[k].x) * std::numbers::pi * merged.texel_area[k];
  EXPECT_NEAR(mapped / s.power_deposited.x, 1.0, 1e-4);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(s.power_sent[c] / emitted[c], 1.0, 1e-5);
    const double ends =
        double(s.power_deposited[c]) + s.power_absorbed[c] + s.power_escaped[c] + s.power_direct[c];
    EXPECT_NEAR(ends / s.power_sent[c], 1.0, 1e-5);
    EXPECT_LT(s.power_escaped[c], 1e-4 * s.power_sent[c]);
    EXPECT_GT(s.power_deposited[c], 0.05f * s.power_sent[c]);
  }
}

TEST(Pass1Shards, EachBatchGoesToTheLeastLoadedShard) {
  // Batches of 4096..8191 rays (WorkItems of up to 4096 closed a batch), a fixed pattern.
  std::vector<uint64_t> rays;
  for (uint64_t k = 0; k < 203; ++k) rays.push_back(4096 + (k * 2654435761u) % 4096);
  for (int count : {1, 3, 4, 7}) {
    const std::vector<int> owner = pass1_batch_shards(rays, count);
    ASSERT_EQ(owner.size(), rays.size());
    EXPECT_EQ(owner, pass1_batch_shards(rays, count));  // depends on the plan alone
    std::vector<uint64_t> load(size_t(count), 0);
    for (size_t b = 0; b < rays.size(); ++b) {
      ASSERT_TRUE(owner[b] >= 0 && owner[b] < count);
      load[size_t(owner[b])] += rays[b];
    }
    const auto [lo, hi] = std::minmax_element(load.begin(), load.end());
    EXPECT_LE(*hi - *lo, 8191u) << count << " shards";  // one batch at most
  }
  EXPECT_EQ(pass1_batch_shards(rays, 4)[0], 0);
  EXPECT_EQ(pass1_batch_shards(rays, 4)[3], 3);  // neighbours spread over the shards
}

TEST(FixedSums, ScaleAndRoundingAreAsDocumented) {
  const FixedScale scale = illumination::fixed_scale({4.0, 0.5, 0.0}, 100'000'000);
  EXPECT_EQ(scale.power_unit.x, std::ldexp(4.0, -54));
  EXPECT_EQ(scale.power_unit.y, std::ldexp(0.5, -54));
  EXPECT_EQ(scale.power_unit.z, 1.0);                  // a dark channel: any unit, all adds 0
  EXPECT_EQ(scale.weight_unit, std::ldexp(1.0, -35));  // 1e8 < 2^27: 62 - 27
  // Each value comes back within half a unit (2^-55 of the lights' 4 W: 1.1e-16 W).
  double worst = 0.0;
  for (int k = 1; k < 1000; ++k) {
    const double value = 4.0 * std::pow(double(k) / 1000.0, 9.0);  // 4e-27 .. 4 W
    const double back =
        double(illumination::to_fixed(value, scale.power_unit.x, "test")) * scale.power_unit.x;
    worst = std::max(worst, std::abs(back - value));
  }
  EXPECT_LE(worst, 0.5 * scale.power_unit.x);  // measured 1.11e-16 W: the bound is reached
  EXPECT_GT(worst, 0.0);                       // it does round
}

TEST(FixedSums, OverflowIsAnErrorNeverAWrap) {
  constexpr int64_t top = std::numeric_limits<int64_t>::max();
  int64_t a = top - 4;
  EXPECT_THROW(illumination::add_checked(a, 5, "test"), FixedOverflow);
  int64_t b = top - 4;
  EXPECT_THROW(illumination::add_checked_atomic(b, 5, "test"), FixedOverflow);
  int64_t c = -top;
  EXPECT_THROW(illumination::add_checked(c, -2, "test"), FixedOverflow);
  EXPECT_THROW(illumination::to_fixed(1e3, 1e-16, "test"), FixedOverflow);  // 1e19 units
  EXPECT_THROW(illumination::to_fixed(std::nan(""), 1.0, "test"), FixedOverflow);
  EXPECT_EQ(illumination::to_fixed(-2.5, 1.0, "test"), -2);  // to nearest, ties to even
  try {
    int64_t d = top;
    illumination::add_checked(d, 1, "texel power");
  } catch (const FixedOverflow& e) {
    EXPECT_NE(std::string(e.what()).find("texel power"), std::string::npos) << e.what();
  }
  Pass1Sums small(4), large(5);
  EXPECT_THROW(small.add(large), std::invalid_argument);
}

// Light groups' sums live in blocks made on a first deposit: against a dense array filled by
// hand, the same units whatever the threads' order, 0 where nothing came, blocks added across
// sums, and overflow and shape errors as the dense sums have them.
TEST(Pass1Sums, GroupPowerBlocksHoldWhatADenseArrayWould) {
  constexpr size_t nodes = 3 * illumination::GroupPower::kNodesPerBlock + 7, groups = 3;
  std::vector<int64_t> dense(groups * nodes * 3, 0);
  illumination::GroupPower sparse(nodes, groups);
  // Deposits on a few nodes of each group, the last (partial) block included, from 2 threads.
  const size_t touched[] = {0, 5, 300, nodes - 1};
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    tbb::parallel_for(0, 4000, [&](int i) {
      const size_t g = size_t(i) % groups, node = touched[size_t(i / 3) % 4];
      sparse.add_atomic(g, node, i / 12 % 3, int64_t(i) - 1000);
    });
  }
  for (int i = 0; i < 4000; ++i)
    dense[(size_t(i) % groups * nodes + touched[size_t(i / 3) % 4]) * 3 + size_t(i / 12 % 3)] +=
        int64_t(i) - 1000;
  illumination::GroupPower twice(nodes, groups);
  twice.add(sparse);
  twice.add(sparse);
  for (size_t g = 0; g < groups; ++g)
    for (size_t k = 0; k < nodes; ++k)
      for (int c = 0; c < 3; ++c) {
        const int64_t expected = dense[(g * nodes + k) * 3 + size_t(c)];
        ASSERT_EQ(sparse.at(g, k, c), expected) << g << " " << k << " " << c;
        ASSERT_EQ(twice.at(g, k, c), 2 * expected) << g << " " << k << " " << c;
      }
  illumination::GroupPower full(nodes, 1);
  full.add_atomic(0, 1, 0, std::numeric_limits<int64_t>::max());
  EXPECT_THROW(full.add_atomic(0, 1, 0, 1), FixedOverflow);
  EXPECT_THROW(twice.add(full), std::invalid_argument);
  illumination::GroupPower moved = std::move(twice);
  EXPECT_EQ(moved.at(2, nodes - 1, 2), 2 * dense[(2 * nodes + nodes - 1) * 3 + 2]);
}

}  // namespace
}  // namespace lb
