// The soft-light texel map (bake/lightmap/soft_texels.h): a closed sphere of uniform albedo
// against its closed form, its power against the resampled solution, the same bits whatever
// the thread count, and the bake directory round trip (soft_light.exr, format 4).

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <glm/gtc/constants.hpp>

#include "bake/contact_conform.h"
#include "bake/lightmap/lightmap.h"
#include "bake/lightmap/soft_texels.h"
#include "bake/lightmap/texel_footprint.h"
#include "bake/sh_projection.h"
#include "bake/pipeline/bake.h"
#include "bake/pipeline/bake_io.h"
#include "scenes.h"
#include "test_helpers.h"

namespace lb {
namespace {

constexpr double pi = glm::pi<double>();

struct MapStats {
  double mean = 0.0;    // area-weighted mean of the red channel over the valid nodes
  double spread = 0.0;  // RMS of node / expected - 1
  double p99 = 0.0;     // 99th percentile of |node / expected - 1|
  double p50 = 0.0;     // its median
};

MapStats stats_against(const BakeResult& bake, const std::vector<vec3>& map, double expected) {
  MapStats s;
  double area = 0.0, sum_sq = 0.0;
  std::vector<double> errors;
  for (size_t k = 0; k < map.size(); ++k) {
    if (!bake.illumination.valid[k] || !(bake.illumination.texel_area[k] > 0.0f)) continue;
    const double a = bake.illumination.texel_area[k];
    s.mean += a * map[k].x;
    area += a;
    const double e = map[k].x / expected - 1.0;
    sum_sq += e * e;
    errors.push_back(std::abs(e));
  }
  s.mean /= area;
  s.spread = std::sqrt(sum_sq / double(std::max<size_t>(errors.size(), 1)));
  std::sort(errors.begin(), errors.end());
  if (!errors.empty()) s.p99 = errors[errors.size() * 99 / 100];
  if (!errors.empty()) s.p50 = errors[errors.size() / 2];
  return s;
}

// A closed sphere (radius 1, inward) of albedo rho with an emitting cap: every point receives
// the same soft light (>= 2 diffuse bounces), rho P / ((1 - rho) pi A) as E/pi, P = pi L_e
// A_cap (tests/radiosity/test_radiosity.cpp, ClosedSphere).
TEST(SoftTexels, ClosedSphereMatchesTheClosedForm) {
  const float rho = 0.7f;
  const Scene scene = test::make_emitting_sphere(rho, 1.0f, 25.0f, 24, 48);
  const double area = double(mesh_area(scene.meshes[0])) + mesh_area(scene.meshes[1]);
  const double expected = rho * pi * mesh_area(scene.meshes[1]) / ((1.0 - rho) * pi * area);
  BakeParams params;  // the default soft-texel settings
  params.radiosity.ray_budget = 1'000'000;
  const BakeResult bake = bake_scene(scene, params);
  ASSERT_EQ(bake.soft_texels.radiance.size(),
            size_t(bake.illumination.width) * size_t(bake.illumination.height));
  EXPECT_GT(bake.soft_texels.gather_rays, 0u);

  SoftTexelParams plain;
  plain.gather_rays = 0;
  const SoftTexelMap resampled = soft_light_texels(scene, bake, plain);
  const MapStats g = stats_against(bake, bake.soft_texels.radiance, expected);
  const MapStats r = stats_against(bake, resampled.radiance, expected);
  std::printf("gathered: mean/expected %.4f spread %.4f p99 %.4f; resampled: %.4f %.4f %.4f\n",
              g.mean / expected, g.spread, g.p99, r.mean / expected, r.spread, r.p99);
  // The mean (the map's power over the surface): measured -0.18% (gathered) and -0.14%
  // (resampled); bound 1%.
  EXPECT_NEAR(g.mean / expected, 1.0, 0.01);
  EXPECT_NEAR(r.mean / expected, 1.0, 0.01);
  // Per node: the gather's noise after the chart filter. RMS measured 0.66% (the resampled
  // solution's 1.3%), bound 1.5%; 99% of nodes within 2.2% (resampled 3.5%), bound 3%. (The
  // worst node, 26% off in both maps, is a sliver at a chart border of the faceted sphere.)
  EXPECT_LT(g.spread, 0.015);
  EXPECT_LT(g.p99, 0.03);
}

// The soft band in the closed sphere above (every wall point, the cap's included, sends the
// same radiance: the soft light is a uniform sky over each texel's hemisphere): L1 = 0, and the
// decode (s = 0) at a normal tilted by t is the uniform sky's closed form, expected x
// (1 + cos t) / 2 (bake/sh_projection.h), the mean over the walls' nodes.
TEST(SoftBand, ClosedSphereIsAUniformSkyAtTiltedNormals) {
  const float rho = 0.7f;
  Scene scene = test::make_emitting_sphere(rho, 1.0f, 25.0f, 24, 48);
  test::add_flat_normal_map(scene, 0);  // the walls take the band (n = n0)
  const double area = double(mesh_area(scene.meshes[0])) + mesh_area(scene.meshes[1]);
  const double expected = rho * pi * mesh_area(scene.meshes[1]) / ((1.0 - rho) * pi * area);
  BakeParams params;
  params.radiosity.ray_budget = 1'000'000;
  params.illumination.directional = true;
  params.soft_band.gather_rays = 16;
  const BakeResult bake = bake_scene(scene, params);
  const SoftTexelMap& soft = bake.soft_texels;
  ASSERT_EQ(soft.l1[0].size(), soft.radiance.size());
  double l1 = 0.0, weight = 0.0, decoded[3] = {0.0, 0.0, 0.0};
  const float tilts[3] = {0.0f, 30.0f, 60.0f};
  for (size_t k = 0; k < soft.radiance.size(); ++k) {
    const double a = bake.illumination.texel_area[k];
    if (!bake.illumination.valid[k] || !(a > 0.0)) continue;
    const vec3 band(soft.l1[0][k].x, soft.l1[1][k].x, soft.l1[2][k].x);
    l1 += a * glm::length(band);
    // The decode's W term depends on the tilt alone; L1 . n, noise about 0 here, is taken in
    // one fixed frame for every node (n0 = +z, n turned about y).
    const ShL1 sh{soft.radiance[k], {soft.l1[0][k], soft.l1[1][k], soft.l1[2][k]}, 0.0f};
    for (int t = 0; t < 3; ++t) {
      const float r = glm::radians(tilts[t]);
      decoded[t] += a * decode_directional(sh, vec3(std::sin(r), 0, std::cos(r)), vec3(0, 0, 1)).x;
    }
    weight += a;
  }
  std::printf("closed sphere's soft band: mean |L1| %.4f of the closed form;",
              l1 / weight / expected);
  for (int t = 0; t < 3; ++t) {
    const double closed = expected * (1.0 + std::cos(glm::radians(double(tilts[t])))) / 2.0;
    std::printf(" %g deg %.4f", double(tilts[t]), decoded[t] / weight / closed);
    // The map's mean within 1% (the test above), the decode's on top: within 1.5% (measured
    // 0.4% at 0, 30 and 60 degrees).
    EXPECT_NEAR(decoded[t] / weight / closed, 1.0, 0.015) << tilts[t] << " degrees";
  }
  std::printf("\n");
  EXPECT_LT(l1 / weight / expected, 0.05);  // the gather's noise, 16 rays a point (2.4%)
}

// The automatic choices (soft_texel_choices): atlases of 65,536 cells or more (the bundled
// scenes at their automatic density) keep 1 point a cell, the gather rays and the box they
// are given; game densities take more points, rays from their own budget and a box of
// half-width 1; an explicit points side keeps the rays and the box.
TEST(SoftTexels, GameDensitiesTakeMoreRaysAndANarrowBox) {
  const SoftTexelParams defaults;
  const SoftTexelParams automatic = soft_texel_choices(defaults, 130'000);
  EXPECT_EQ(automatic.points_side, 1);
  EXPECT_EQ(automatic.gather_rays, 8);
  EXPECT_EQ(automatic.filter_radius, 10);
  EXPECT_EQ(automatic.filter_fit, ChartFit::mean_at_node);
  // The Cornell box at 20 texels/m touches ~8,500 cells: 5 x 5 points, 262144 x 20 rays over
  // 212,500 points = 24 a point.
  const SoftTexelParams twenty = soft_texel_choices(defaults, 8'500);
  EXPECT_EQ(twenty.points_side, 5);
  EXPECT_EQ(twenty.gather_rays, 24);
  EXPECT_EQ(twenty.filter_radius, 1);
  EXPECT_EQ(twenty.filter_fit, ChartFit::mean);  // a 3 x 3 box: its slope too noisy at seams
  // Under 4,096 cells 8 x 8 points; under 1,280 the rays reach their cap.
  EXPECT_EQ(soft_texel_choices(defaults, 2'000).gather_rays, 40);
  EXPECT_EQ(soft_texel_choices(defaults, 600).gather_rays, kSoftMaxGatherRays);
  // Never fewer rays than asked; no gather stays none.
  SoftTexelParams many = defaults;
  many.gather_rays = 100;
  EXPECT_EQ(soft_texel_choices(many, 8'500).gather_rays, 100);
  SoftTexelParams none = defaults;
  none.gather_rays = 0;
  EXPECT_EQ(soft_texel_choices(none, 8'500).gather_rays, 0);
  SoftTexelParams given = defaults;
  given.points_side = 5;
  EXPECT_EQ(soft_texel_choices(given, 8'500).gather_rays, 8);
  EXPECT_EQ(soft_texel_choices(given, 8'500).filter_radius, 2);
}

// The closed sphere at 5 texels/m (314 cells: 8 x 8 points a cell, 64 rays a point) against
// its closed form, and its noise (two seeds' maps) against the rule before game densities had
// rays of their own (8 rays a point, the same points and box); the same bits on one and two
// threads. (Per node the faceted sphere is 1.9% RMS off the round one's closed form in both
// maps: the facets' geometry, not the rays.)
TEST(SoftTexels, ClosedSphereAtAGameDensity) {
  const float rho = 0.7f;
  const Scene scene = test::make_emitting_sphere(rho, 1.0f, 25.0f, 24, 48);
  const double area = double(mesh_area(scene.meshes[0])) + mesh_area(scene.meshes[1]);
  const double expected = rho * pi * mesh_area(scene.meshes[1]) / ((1.0 - rho) * pi * area);
  BakeParams params;
  params.radiosity.ray_budget = 1'000'000;
  params.illumination.texel_size = 0.2f;
  params.soft_texels.gather_rays = 0;  // the maps below
  const BakeResult bake = bake_scene(scene, params);
  SoftTexelParams now;
  SoftTexelParams before = now;
  before.points_side = 8;  // given: 8 rays a point, box half-width 10 / 8 = 1
  const auto map = [&](SoftTexelParams soft, uint64_t seed) {
    soft.seed = seed;
    return soft_light_texels(scene, bake, soft).radiance;
  };
  std::vector<vec3> one, two;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = map(now, 11);
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    two = map(now, 11);
  }
  ASSERT_FALSE(one.empty());
  EXPECT_TRUE(test::same_bits(one, two));
  const std::vector<vec3> now_b = map(now, 12), was_a = map(before, 11), was_b = map(before, 12);
  const auto seed_to_seed = [&](const std::vector<vec3>& a, const std::vector<vec3>& b) {
    double sum_sq = 0.0;
    size_t nodes = 0;
    for (size_t k = 0; k < a.size(); ++k) {
      if (!bake.illumination.valid[k] || !(bake.illumination.texel_area[k] > 0.0f)) continue;
      const double e = double(a[k].x - b[k].x) / expected;
      sum_sq += e * e;
      ++nodes;
    }
    return std::sqrt(sum_sq / double(std::max<size_t>(nodes, 1)));
  };
  const MapStats s = stats_against(bake, one, expected);
  const double noise_now = seed_to_seed(one, now_b), noise_was = seed_to_seed(was_a, was_b);
  std::printf("5 texels/m: mean/expected %.4f (8 rays %.4f), per node RMS %.4f median %.4f; "
              "seed to seed RMS %.4f (8 rays %.4f)\n", s.mean / expected,
              stats_against(bake, was_a, expected).mean / expected, s.spread, s.p50, noise_now,
              noise_was);
  // The power: measured -0.20% (8 rays: -0.22%); bound 0.5%.
  EXPECT_NEAR(s.mean / expected, 1.0, 0.005);
  // The noise: measured 0.0015 against 0.0023 (the radiosity solution's own noise, read at the
  // gather's hits, is the rest); bound 0.8x.
  EXPECT_LT(noise_now, 0.8 * noise_was);
}

// The gather corrects the solution's bias but must keep its power where the solution is
// right: the room (blocks, contacts) at the default settings, the map's power (sum of value x
// texel area) against the resampled solution's.
TEST(SoftTexels, PowerStaysNearTheResampledSolution) {
  const Scene scene = test::make_room();
  BakeParams params;
  params.radiosity.ray_budget = 200'000;
  const BakeResult bake = bake_scene(scene, params);
  SoftTexelParams plain;
  plain.gather_rays = 0;
  const SoftTexelMap resampled = soft_light_texels(scene, bake, plain);
  glm::dvec3 gathered(0.0), base(0.0);
  for (size_t k = 0; k < resampled.radiance.size(); ++k) {
    if (!bake.illumination.valid[k]) continue;
    gathered += double(bake.illumination.texel_area[k]) * glm::dvec3(bake.soft_texels.radiance[k]);
    base += double(bake.illumination.texel_area[k]) * glm::dvec3(resampled.radiance[k]);
  }
  for (int c = 0; c < 3; ++c) {
    std::printf("channel %d: gathered / resampled power %.4f\n", c, gathered[c] / base[c]);
    // Measured 0.993 in every channel (the gather finds 0.7% less than the solution); bound 3%.
    EXPECT_NEAR(gathered[c] / base[c], 1.0, 0.03) << "channel " << c;
  }
}

// The room's soft-light map made twice with other seeds: the RMS over its nodes of the two
// maps' difference relative to the resampled solution (the correction's noise).
class RoomMapNoise {
 public:
  RoomMapNoise() : scene_(test::make_room()) {
    BakeParams params;
    params.radiosity.ray_budget = 200'000;
    params.soft_texels.gather_rays = 0;
    bake_ = bake_scene(scene_, params);
    SoftTexelParams plain;
    plain.gather_rays = 0;
    base_ = soft_light_texels(scene_, bake_, plain).radiance;
  }

  double seed_to_seed(SoftTexelParams soft) const {
    soft.seed = 11;
    const std::vector<vec3> a = soft_light_texels(scene_, bake_, soft).radiance;
    soft.seed = 12;
    const std::vector<vec3> b = soft_light_texels(scene_, bake_, soft).radiance;
    double sum_sq = 0.0;
    size_t nodes = 0;
    for (size_t k = 0; k < base_.size(); ++k) {
      if (!bake_.illumination.valid[k] || !(base_[k].x > 0.0f)) continue;
      const double e = double(a[k].x - b[k].x) / double(base_[k].x);
      sum_sq += e * e;
      ++nodes;
    }
    return std::sqrt(sum_sq / double(std::max<size_t>(nodes, 1)));
  }

 private:
  Scene scene_;
  BakeResult bake_;
  std::vector<vec3> base_;
};

// The box before the proximity radii: 6 texels everywhere, at the 4 rays of that time.
SoftTexelParams fixed_box() {
  SoftTexelParams soft;
  soft.gather_rays = 4;
  soft.filter_radius = 6;
  soft.filter_reach = 0.0f;
  return soft;
}

// Interleaved strata (bake/lightmap/interleaved_strata.h) spend the same rays better in whole
// boxes: measured with the fixed 6-texel box and its plain mean. They are off by default
// (soft_texels.h): in boxes the chart's border clips or a contact narrows, their quadrants no
// longer balance (the Cornell box's contacts against Cycles, bench/results/LOG.md).
TEST(SoftTexels, InterleavedStrataLowerTheNoiseInWholeBoxes) {
  const RoomMapNoise room;
  SoftTexelParams soft = fixed_box();
  soft.filter_fit = ChartFit::mean;
  soft.strata_levels = 0;
  const double none = room.seed_to_seed(soft);
  soft.strata_levels = 1;
  const double strata = room.seed_to_seed(soft);
  std::printf("seed-to-seed RMS: no strata %.4f, interleaved %.4f (ratio %.3f)\n", none, strata,
              strata / none);
  // Measured 0.0121 without strata, 0.0117 with one level; two levels 0.0132 and three 0.0187
  // (a node's own four cells then miss most sub-squares, and the chart filter is clipped at
  // borders). Bound: below none, by 1%.
  EXPECT_LT(strata, 0.99 * none);
}

// The proximity boxes (soft_texels.h) narrow the filter near contacts and widen it in the open:
// over the room's nodes the map is less noisy than with the fixed box, so the radii themselves
// do not vary from seed to seed (1/d's heavy tail did that before its floor and smoothing).
TEST(SoftTexels, ProximityBoxesAreNoNoisierThanAFixedBox) {
  const RoomMapNoise room;
  const double fixed = room.seed_to_seed(fixed_box());
  const double proximity = room.seed_to_seed(SoftTexelParams{});
  std::printf("seed-to-seed RMS: fixed 6-texel box %.4f, proximity boxes %.4f (ratio %.3f)\n",
              fixed, proximity, proximity / fixed);
  // The fixed box at 4 rays, the map's earlier default, against today's defaults (8 rays and
  // up to 4 x where boxes narrow, reach 0.25, no strata), both with the mean moved to the node:
  // measured 0.0129 and 0.0116 (reach 0.7, one level of strata, 8 rays: 0.0128, 0.0117; with the
  // plain mean 0.0117 and 0.0109; reach 0.5 at 8 rays measured 0.0122 against 0.0117 then,
  // which this bound caught, as it did 0.0208 without the distance floor and its smoothing,
  // kNearestTexels 1e-4 m, kProximitySmoothing 0).
  EXPECT_LT(proximity, fixed);
}

// A quick bake of the room with a mirror (caustics and specular hits too).
BakeParams small_params(int gather_rays) {
  BakeParams params;
  params.illumination.rays_per_zone_side = 16;
  params.radiosity.ray_budget = 50'000;
  params.soft_texels.gather_rays = gather_rays;
  return params;
}

TEST(SoftTexels, SameBitsWhateverTheThreadCount) {
  const Scene scene = test::make_room_with_mirror();
  const BakeResult bake = bake_scene(scene, small_params(0));
  SoftTexelParams soft;
  soft.gather_rays = 2;
  std::vector<vec3> one, two;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = soft_light_texels(scene, bake, soft).radiance;
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    two = soft_light_texels(scene, bake, soft).radiance;
  }
  ASSERT_FALSE(one.empty());
  EXPECT_TRUE(test::same_bits(one, two));
}

TEST(SoftTexels, SavedWithTheBakeAndReadBackBitForBit) {
  const Scene scene = test::make_room_with_mirror();
  const BakeParams params = small_params(2);
  const BakeResult bake = bake_scene(scene, params);
  const std::string dir = test::fresh_dir("soft_texels", "round_trip");
  save_bake(dir, scene, bake, params);
  const BakeResult back = load_bake(dir, scene);
  EXPECT_TRUE(test::same_bits(bake.soft_texels.radiance, back.soft_texels.radiance));
  EXPECT_EQ(back.soft_texels.gather_rays, bake.soft_texels.gather_rays);
  EXPECT_GT(bake.soft_texels.distance_rays, 0u);  // the proximity radii's rays are counted
  EXPECT_EQ(back.soft_texels.distance_rays, bake.soft_texels.distance_rays);

  // A bake of the previous format is refused with the version in the message.
  const std::string manifest = (std::filesystem::path(dir) / "manifest.json").string();
  std::ifstream in(manifest);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  in.close();
  const size_t at = text.find("\"version\": 7");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 12, "\"version\": 4");
  std::ofstream(manifest) << text;
  try {
    load_bake(dir, scene);
    FAIL() << "a format-4 bake loaded";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("format version 4, this build reads 5 to 7"),
              std::string::npos)
        << e.what();
  }
}

// The view factor from a point x on the floor (normal +y) to the convex polygon `v` (counter-
// clockwise seen from x or not: the sign is taken off), by Lambert's formula for a polygon:
// F = 1 / (2 pi) |sum_i angle(R_i, R_i+1) n . unit(R_i x R_i+1)|, R_i = v_i - x.
double point_to_polygon_view_factor(glm::dvec3 x, const std::vector<glm::dvec3>& v) {
  double sum = 0.0;
  for (size_t i = 0; i < v.size(); ++i) {
    const glm::dvec3 a = v[i] - x, b = v[(i + 1) % v.size()] - x;
    const glm::dvec3 c = glm::cross(a, b);
    if (glm::length(c) == 0.0) continue;
    const double angle = std::acos(std::clamp(glm::dot(a, b) / (glm::length(a) * glm::length(b)),
                                              -1.0, 1.0));
    sum += angle * glm::normalize(c).y;
  }
  return std::abs(sum) / (2.0 * pi);
}

// A black 60 x 60 x 10 cm block standing on a floor under a uniform sky of radiance 1: a floor
// point sees the sky and the block only, so its soft light (E / pi) is 1 - F, F its view factor
// to the block's sides (closed form: Lambert's polygon formula over the sides that face it). At
// 1.5 cm texels the floor darkens from 0.8 to 0.9 within 4 texels of the foot, where the soft
// map's correction box (half-width 0.7 x the harmonic distance to the block before 8 Dec 2026)
// smeared the darkening: the floor's nodes there too bright. The reference: the closed form's
// mean over each node's footprint, on the same atlas (fill_texels). The control is the rule
// before: reach 0.7, interleaved strata, the same rays everywhere.
TEST(SoftTexels, TheFloorAtABlocksFootUnderASkyMatchesItsViewFactor) {
  Scene scene;
  Material black;
  black.reflectance = vec3(0.0f);
  const int floor_material = test::add_material(scene, Material{});
  const int block_material = test::add_material(scene, black);
  scene.meshes.push_back(test::make_quad({-1, 0, 1}, {2, 0, 0}, {0, 0, -2}, floor_material,
                                         "floor"));
  const double lo = -0.3, hi = 0.3, height = 0.1;
  scene.meshes.push_back(test::make_box(vec3(float(lo), 0.0f, float(lo)),
                                        vec3(float(hi), float(height), float(hi)), block_material,
                                        false, "block"));
  scene.sky = Sky(vec3(1.0f));
  conform_to_contacts(scene);
  const auto closed_form = [&](vec3 p) {
    const glm::dvec3 x(p);
    const glm::dvec3 up(0.0, height, 0.0);
    // The block's side over floor edge a-b.
    const auto side = [&](glm::dvec3 a, glm::dvec3 b) {
      return point_to_polygon_view_factor(x, {a, b, b + up, a + up});
    };
    double f = 0.0;
    if (x.x < lo) f += side({lo, 0, lo}, {lo, 0, hi});
    if (x.x > hi) f += side({hi, 0, lo}, {hi, 0, hi});
    if (x.z < lo) f += side({lo, 0, lo}, {hi, 0, lo});
    if (x.z > hi) f += side({lo, 0, hi}, {hi, 0, hi});
    return 1.0 - f;
  };
  // Signed and absolute mean relative error of the floor's nodes 1 to 4.5 texels out.
  struct FootError {
    double signed_error = 0.0, abs_error = 0.0;
    size_t nodes = 0;
  };
  const auto foot_error = [&](const SoftTexelParams& soft) {
    BakeParams params;
    params.illumination.texel_size = 0.015f;  // not a game density: under 1.5 x 2.9 m / 256
    params.radiosity.ray_budget = 400'000;
    params.soft_texels = soft;
    const BakeResult bake = bake_scene(scene, params);
    std::vector<Mesh> storage;
    const std::vector<const Mesh*> surfaces = lightmap_surfaces(scene, bake, storage);
    const TexelFootprints footprints(surfaces, bake.illumination.width, bake.illumination.height);
    // Layer 0 the closed form, layer 1 the position (the footprint's tent mean), mesh in z.
    FillTexelsParams fill;
    fill.rule = FootprintRule::stratified;
    fill.side = 6;
    const std::vector<std::vector<vec3>> reference = fill_texel_layers(
        footprints, 2,
        [&](std::span<const FootprintSample> samples, std::span<vec3> values, size_t) {
          for (size_t s = 0; s < samples.size(); ++s) {
            values[s] = vec3(float(closed_form(samples[s].position)));
            values[samples.size() + s] = samples[s].position;
          }
        },
        fill);
    const float texel = bake.illumination.texel_size;
    FootError e;
    for (size_t k = 0; k < reference[0].size(); ++k) {
      const vec3 p = reference[1][k];
      if (!bake.illumination.valid[k] || !(bake.illumination.texel_area[k] > 0.0f)) continue;
      if (std::abs(p.y) > 1e-4f) continue;  // the floor's nodes only
      const float out = std::max(std::abs(p.x), std::abs(p.z)) - float(hi);
      // Nodes whose footprint lies wholly on the open floor (centroid a texel out or more: the
      // closed form is not the floor's light under the block).
      if (out < texel || out > 4.5f * texel) continue;
      const double ref = reference[0][k].x;
      const double rel = (double(bake.soft_texels.radiance[k].x) - ref) / ref;
      e.signed_error += rel, e.abs_error += std::abs(rel), ++e.nodes;
    }
    e.signed_error /= double(std::max<size_t>(e.nodes, 1));
    e.abs_error /= double(std::max<size_t>(e.nodes, 1));
    return e;
  };
  SoftTexelParams control;
  control.filter_reach = 0.7f;
  control.strata_levels = 1;
  control.box_rays_max = 1;
  const FootError now = foot_error(SoftTexelParams{}), before = foot_error(control);
  std::printf("the floor 1-4 texels from the block's foot (%zu nodes): signed %+.4f, MRE %.4f; "
              "control (the rule before) %+.4f, %.4f\n",
              now.nodes, now.signed_error, now.abs_error, before.signed_error, before.abs_error);
  RecordProperty("foot_mre", std::to_string(now.abs_error));
  RecordProperty("control_foot_mre", std::to_string(before.abs_error));
  EXPECT_GT(now.nodes, 400u);
  // Measured 0.94% (-0.03% signed), the control 3.5% (+2.7%); with the foot's own narrower box
  // of 7 Dec 2026 (now gone: the rays following the box do better) 2.9% (+2.2%).
  EXPECT_LT(now.abs_error, 0.015);
  EXPECT_LT(now.abs_error, 0.5 * before.abs_error);
}

}  // namespace
}  // namespace lb
