// The one-shadow-ray estimator of section 3.3: unbiased against one shadow ray per light,
// correct next to a large light, and it never sends more than one shadow ray.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "bake/transport/direct_light.h"
#include "bake/sampling.h"
#include "hq_scenes.h"
#include "test_helpers.h"

namespace lb {
namespace {

struct RunningMean {
  double sum = 0.0, sum_sq = 0.0;
  uint64_t n = 0;
  void add(double v) {
    sum += v;
    sum_sq += v * v;
    ++n;
  }
  double mean() const { return sum / double(n); }
  double variance_of_mean() const {
    const double m = mean();
    return std::max(sum_sq / double(n) - m * m, 0.0) / double(n);
  }
};

ReceiverPoint receiver(vec3 p, vec3 n) {
  return {p, n, n};
}

// At each receiver: the mean of kSamples one-shadow-ray estimates against as many every-light
// estimates, within 5 standard deviations of their difference (from the measured variances),
// and that bound under 4% of the value, so that a real bias of a few percent would fail.
// Adds the shadow rays each side sent to one_rays and every_rays.
constexpr int kSamples = 40000;
void expect_one_ray_matches_every_light(const DirectLight& direct, const ReceiverPoint& x,
                                        uint64_t seed, uint64_t& one_rays, uint64_t& every_rays) {
  Rng rng(hash_seed(seed, uint64_t(x.position.x * 1000), uint64_t(x.position.z * 1000)));
  RunningMean one, every;
  std::vector<vec2> u_points(direct.light_count());
  for (int s = 0; s < kSamples; ++s) {
    const DirectEstimate e = direct.one_shadow_ray(x, rng.next_float(), rng.next_2d());
    one_rays += e.shadow_ray ? 1 : 0;
    one.add(luminance(e.value));
    for (vec2& u : u_points) u = rng.next_2d();
    every.add(luminance(direct.every_light(x, u_points.data(), every_rays)));
  }
  const double bound = 5.0 * std::sqrt(one.variance_of_mean() + every.variance_of_mean());
  SCOPED_TRACE(testing::Message() << "point " << x.position.x << "," << x.position.y << ","
                                  << x.position.z << " one " << one.mean() << " every "
                                  << every.mean() << " bound " << bound);
  EXPECT_GT(every.mean(), 0.01);
  EXPECT_LT(bound, 0.04 * every.mean());
  EXPECT_NEAR(one.mean(), every.mean(), bound);
}

// (a) On Figure 5's nine-light room with a table casting partial shadows: the mean of the
// one-shadow-ray estimate converges to the mean of one shadow ray per light. 40,000 independent
// samples of each per point; the means must agree within 5 standard deviations of their
// difference (from the measured variances), and that bound must itself be under 4% of the
// value so that a real bias of a few percent would fail the test.
TEST(DirectLight, OneShadowRayIsUnbiasedOnNineLightRoom) {
  const Scene scene = test::make_light_grid_room(3);
  const Accel accel(scene);
  const DirectLight direct(scene, accel);
  ASSERT_EQ(direct.lights().size(), 9u);

  const vec3 up(0, 1, 0);
  const ReceiverPoint points[] = {
      receiver({0.8f, 0.0f, 0.1f}, up),   // under the table: sees parts of the outer lights
      receiver({1.1f, 0.0f, 0.3f}, up),   // penumbra at the table's edge
      receiver({0.6f, 0.0f, -1.3f}, up),  // penumbra, other side
      receiver({-2.5f, 0.0f, 2.5f}, up),  // corner of the floor
      receiver({0.2f, 1.0f, 0.1f}, up),   // table top, in full light
      receiver({2.999f, 1.5f, 0.4f}, {-1, 0, 0}),  // a wall: lights at grazing angles
  };
  for (const ReceiverPoint& x : points) {
    uint64_t one_rays = 0, every_rays = 0;
    expect_one_ray_matches_every_light(direct, x, 7, one_rays, every_rays);
    EXPECT_LE(one_rays, uint64_t(kSamples));  // never more than one shadow ray per estimate
    EXPECT_GT(every_rays, 4 * one_rays);      // while the reference pays for every light
  }
}

// The same with lamps among the area lights (issue 14): a point lamp under the ceiling and a
// spot aimed at the table's edge are chosen by their exact Eq. 2 value beside the nine
// lights' estimates; the one-shadow-ray mean still matches one shadow ray per light.
TEST(DirectLight, OneShadowRayIsUnbiasedWithLampsAmongAreaLights) {
  Scene scene = test::make_light_grid_room(3);
  Lamp point;
  point.kind = LampKind::point;
  point.position = vec3(-1.5f, 2.5f, 1.0f);
  point.intensity = vec3(2.0f, 1.5f, 1.0f);
  Lamp spot = point;
  spot.kind = LampKind::spot;
  spot.position = vec3(2.0f, 2.5f, -2.0f);
  spot.direction = glm::normalize(vec3(1.0f, 0.0f, 0.0f) - spot.position);
  spot.inner_cone = 0.2f;
  spot.outer_cone = 0.5f;
  scene.lights = {point, spot};
  const Accel accel(scene);
  const DirectLight direct(scene, accel);
  ASSERT_EQ(direct.light_count(), 11u);
  const vec3 up(0, 1, 0);
  const ReceiverPoint points[] = {
      receiver({0.8f, 0.0f, 0.1f}, up),            // under the table
      receiver({1.1f, 0.0f, 0.3f}, up),            // penumbra, in the spot's cone
      receiver({-1.5f, 0.0f, 1.0f}, up),           // below the point lamp
      receiver({2.999f, 1.5f, 0.4f}, {-1, 0, 0}),  // a wall
  };
  for (const ReceiverPoint& x : points) {
    uint64_t one_rays = 0, every_rays = 0;
    expect_one_ray_matches_every_light(direct, x, 11, one_rays, every_rays);
    EXPECT_LE(one_rays, uint64_t(kSamples));
  }
  // Below the point lamp with every area light switched off, the estimate is exact at once:
  // rho-free E/pi = I / (pi h^2) (h = 2.5 m), luminance-weighted.
  for (Material& m : scene.materials) m.emission = vec3(0.0f);
  scene.lights = {point};
  const Accel dark_accel(scene);
  const DirectLight lamp_only(scene, dark_accel);
  ASSERT_EQ(lamp_only.light_count(), 1u);
  const DirectEstimate e =
      lamp_only.one_shadow_ray(receiver({-1.5f, 0.0f, 1.0f}, up), 0.3f, {0.5f, 0.5f});
  const double expected = luminance(point.intensity) / (std::numbers::pi * 2.5 * 2.5);
  EXPECT_NEAR(luminance(e.value), expected, 1e-6 * expected);
}

// The reused light choice (HqParams::reuse_light_choice) is unbiased at any hit, whatever
// anchor it was prepared at: here anchors 0.4 m away on the same surface, and one on the
// ceiling (where no light reaches, so the choice is uniform). Same bound as above.
TEST(DirectLight, ReusedChoiceIsUnbiasedAwayFromItsAnchor) {
  const Scene scene = test::make_light_grid_room(3);
  const Accel accel(scene);
  const DirectLight direct(scene, accel);
  const vec3 up(0, 1, 0);
  const ReceiverPoint points[] = {receiver({1.1f, 0.0f, 0.3f}, up),
                                  receiver({0.8f, 0.0f, 0.1f}, up),
                                  receiver({-2.5f, 0.0f, 2.5f}, up)};
  for (const ReceiverPoint& x : points) {
    for (const ReceiverPoint& anchor :
         {receiver(x.position + vec3(0.4f, 0.0f, -0.3f), up), receiver({0, 3, 0}, -up)}) {
      DirectLight::Choice choice;
      direct.prepare_choice(anchor, 0, choice);
      Rng rng(hash_seed(11, uint64_t(anchor.position.y * 10), uint64_t(x.position.x * 1000)));
      RunningMean reused, every;
      std::vector<vec2> u_points(direct.lights().size());
      uint64_t every_rays = 0;
      for (int s = 0; s < kSamples; ++s) {
        reused.add(
            luminance(direct.one_shadow_ray(x, choice, rng.next_float(), rng.next_2d()).value));
        for (vec2& u : u_points) u = rng.next_2d();
        every.add(luminance(direct.every_light(x, u_points.data(), every_rays)));
      }
      const double bound = 5.0 * std::sqrt(reused.variance_of_mean() + every.variance_of_mean());
      SCOPED_TRACE(testing::Message()
                   << "point " << x.position.x << " anchor y " << anchor.position.y << " reused "
                   << reused.mean() << " every " << every.mean());
      EXPECT_LT(bound, 0.06 * every.mean());
      EXPECT_NEAR(reused.mean(), every.mean(), bound);
    }
  }
}

// The reused choice's search (a count of CDF entries <= u, block by block; a binary search past
// 512 lights; none with one light) picks the light std::upper_bound picks, at u on a fine grid
// and exactly at every CDF entry, for 1, 100 and 576 lights.
TEST(DirectLight, ReusedChoicePicksTheLightUpperBoundFinds) {
  for (const int per_side : {1, 10, 24}) {
    const Scene scene = test::make_light_grid_room(per_side);
    const Accel accel(scene);
    const DirectLight direct(scene, accel);
    const ReceiverPoint x = receiver({0.3f, 0.0f, -0.7f}, vec3(0, 1, 0));
    DirectLight::Choice choice;
    direct.prepare_choice(x, 0, choice);
    const size_t lights = direct.light_count();
    ASSERT_EQ(choice.lights, lights);
    const auto first = choice.cdf.begin(), last = first + std::ptrdiff_t(lights);
    ASSERT_TRUE(std::is_sorted(first, last));  // what the count relies on
    std::vector<float> us;
    for (int k = 0; k < 4096; ++k) us.push_back((float(k) + 0.5f) / 4096.0f);
    for (auto it = first; it + 1 < last; ++it) {
      us.push_back(*it);
      us.push_back(std::nextafter(*it, 0.0f));
    }
    for (const float u : us) {
      Ray ray;
      const DeferredEstimate e = direct.sample_one_light(x, choice, u, vec2(0.5f), ray);
      const size_t expected =
          std::min(size_t(std::upper_bound(first, last, u) - first), lights - 1);
      ASSERT_EQ(e.light, int(expected)) << per_side * per_side << " lights, u = " << u;
    }
  }
}

TEST(DirectLight, NoLightReachableSendsNoShadowRay) {
  const Scene scene = test::make_light_grid_room(3);
  const Accel accel(scene);
  const DirectLight direct(scene, accel);
  // A ceiling point is behind every light's plane: Eq. 2 is zero for all, as in the paper's
  // Figure 5 ("no direct lighting on the ceiling"), so no shadow ray may be traced.
  const ReceiverPoint ceiling = receiver({0.3f, 3.0f, 0.2f}, {0, -1, 0});
  for (float u : {0.0f, 0.3f, 0.99f}) {
    const DirectEstimate e = direct.one_shadow_ray(ceiling, u, {0.5f, 0.5f});
    EXPECT_FALSE(e.shadow_ray);
    EXPECT_EQ(e.value, vec3(0.0f));
  }
  for (float p : direct.selection_probabilities(ceiling)) EXPECT_EQ(p, 0.0f);
}

TEST(DirectLight, SelectionFollowsEq2WithAUniformShare) {
  const Scene scene = test::make_light_grid_room(3);
  const Accel accel(scene);
  const DirectLight direct(scene, accel);
  const ReceiverPoint x = receiver({-2.0f, 0.0f, -2.0f}, {0, 1, 0});  // under one corner light
  const std::vector<float> p = direct.selection_probabilities(x);
  double total = 0.0, eq2_total = 0.0;
  for (size_t j = 0; j < p.size(); ++j) {
    total += p[j];
    eq2_total += direct.eq2_estimate(x, j);
  }
  EXPECT_NEAR(total, 1.0, 1e-5);
  for (size_t j = 0; j < p.size(); ++j) {
    const double expected =
        (1.0 - DirectLight::kUniformShare) * direct.eq2_estimate(x, j) / eq2_total +
        DirectLight::kUniformShare / double(p.size());
    EXPECT_NEAR(p[j], expected, 1e-5);
  }
  // The nearest, brightest light is the likeliest target (the paper's intent).
  const size_t nearest = size_t(std::max_element(p.begin(), p.end()) - p.begin());
  EXPECT_LT(glm::length(direct.lights()[nearest].centroid - vec3(-2.0f, 2.99f, -2.0f)), 1e-3f);
}

// Lambert's closed form as E/pi (the convention of bake/bake_result.h); vertices wound
// either way.
double polygon_irradiance_over_pi(const std::vector<vec3>& vertices, vec3 point, vec3 normal,
                                  double radiance) {
  const std::vector<glm::dvec3> polygon(vertices.begin(), vertices.end());
  return test::polygon_irradiance(polygon, glm::dvec3(point), glm::dvec3(normal), radiance) /
         std::numbers::pi;
}

// (b) Near a large light, where Eq. 2 at the centre is wrong by a large factor, the estimate
// (sampled point, not centre) matches Lambert's closed form within 1%. 512 x 512 stratified
// points on the light, light choice jittered over 262,144 strata; a second, distant light makes
// the choice matter.
TEST(DirectLight, NearALargeLightMatchesPolygonIrradiance) {
  Scene scene;
  Material lamp;
  lamp.emission = vec3(4.0f);
  lamp.reflectance = vec3(0.0f);
  const int lamp_material = test::add_material(scene, lamp);
  // A 1 x 1 m light at y = 1 facing down, and a small one far to the side.
  scene.meshes.push_back(test::make_quad({-0.5f, 1, -0.5f}, {1, 0, 0}, {0, 0, 1}, lamp_material));
  scene.meshes.push_back(test::make_quad({6.0f, 3, 0}, {0.2f, 0, 0}, {0, 0, 0.2f}, lamp_material));
  const Accel accel(scene);
  const DirectLight direct(scene, accel);
  const std::vector<vec3> corners = {
      {-0.5f, 1, -0.5f}, {0.5f, 1, -0.5f}, {0.5f, 1, 0.5f}, {-0.5f, 1, 0.5f}};

  struct Case {
    vec3 point;
    vec3 normal;
  };
  const Case cases[] = {
      {{0.0f, 0.8f, 0.0f}, {0, 1, 0}},                          // 20 cm under the centre
      {{0.4f, 0.9f, 0.35f}, {0, 1, 0}},                         // 10 cm under a corner region
      {{0.1f, 0.85f, 0.0f}, glm::normalize(vec3(0.2f, 1, 0))},  // tilted, light all above it
  };
  constexpr int kSide = 512;
  for (const Case& c : cases) {
    // Lambert's formula needs the whole polygon above the horizon: true for all three cases.
    const ReceiverPoint x = receiver(c.point, c.normal);
    const double exact =
        polygon_irradiance_over_pi(corners, c.point, c.normal, 4.0) +
        polygon_irradiance_over_pi({{6.0f, 3, 0}, {6.2f, 3, 0}, {6.2f, 3, 0.2f}, {6.0f, 3, 0.2f}},
                                   c.point, c.normal, 4.0);
    Rng rng(99);
    double sum = 0.0;
    for (int i = 0; i < kSide; ++i)
      for (int k = 0; k < kSide; ++k) {
        const float u_select = (float(i * kSide + k) + rng.next_float()) / float(kSide * kSide);
        const vec2 u_point = stratified(int(rng.next_u32() % kSide), int(rng.next_u32() % kSide),
                                        kSide, kSide, rng.next_2d());
        sum += direct.one_shadow_ray(x, u_select, u_point).value.x;
      }
    const double mean = sum / double(kSide * kSide);
    SCOPED_TRACE(testing::Message() << "mean " << mean << " exact " << exact);
    EXPECT_NEAR(mean, exact, 0.01 * exact);
    // Eq. 2's point form at the centre, L A cos1 cos2 / (pi d^2), is far off here: the reason
    // the returned value must use the sampled point.
    const vec3 to_centre = vec3(0, 1, 0) - c.point;
    const double d2 = glm::dot(to_centre, to_centre);
    const double cos1 = glm::dot(c.normal, to_centre) / std::sqrt(d2);
    const double cos2 = to_centre.y / std::sqrt(d2);
    const double point_form = 4.0 * 1.0 * cos1 * cos2 / (std::numbers::pi * d2);
    EXPECT_GT(std::abs(point_form - exact), 0.5 * exact);
  }
}

// A double-sided emissive square lights the floor above it as the floor below (glTF
// doubleSided): each gets Lambert's irradiance of one face. Before: nothing above.
TEST(DirectLight, DoubleSidedEmitterLightsTheFloorAboveAndBelow) {
  const float radiance = 4.0f;
  const test::TwoSidedPanel panel = test::make_two_sided_panel(1.0f, radiance, 0.2f, 0.5f);
  const Accel accel(panel.scene);
  const DirectLight direct(panel.scene, accel);
  const std::vector<vec3> corners(panel.corners.begin(), panel.corners.end());
  constexpr int kSide = 256;
  for (const float y : {0.2f, -0.2f}) {
    const vec3 p(0.3f, y, 0.1f), n(0.0f, y > 0.0f ? -1.0f : 1.0f, 0.0f);
    const ReceiverPoint x = receiver(p, n);  // on the floor
    const double exact = polygon_irradiance_over_pi(corners, x.position, n, radiance);
    Rng rng(98);
    double sum = 0.0;
    for (int i = 0; i < kSide; ++i)
      for (int k = 0; k < kSide; ++k)
        sum += direct.one_shadow_ray(x, rng.next_float(), stratified(i, k, kSide, kSide,
                                                                     rng.next_2d()))
                   .value.x;
    EXPECT_NEAR(sum / (kSide * kSide), exact, 0.01 * exact) << "y " << y;
  }
}

// glTF alphaMode MASK: the floor under a leaf whose alpha checker cuts half its area gets half
// the sun, E/pi = 0.5 x 3/pi averaged over the leaf's shadow; outside it the whole sun. Before:
// the leaf cast a solid shadow (0).
// The mean direct light over the floor under the leaf (x, z in [-0.5, 0.5]), 64 x 64 stratified
// points, one shadow ray each; each ray is traced twice and must get the same answer.
double mean_light_under_leaf(const DirectLight& direct) {
  constexpr int kSide = 64;
  Rng rng(3);
  double sum = 0.0;
  for (int i = 0; i < kSide; ++i)
    for (int k = 0; k < kSide; ++k) {
      const vec2 u = stratified(i, k, kSide, kSide, rng.next_2d());
      const ReceiverPoint x = receiver({u.x - 0.5f, 0.0f, u.y - 0.5f}, {0, 1, 0});
      const float once = direct.one_shadow_ray(x, 0.5f, vec2(0.5f)).value.x;
      EXPECT_EQ(direct.one_shadow_ray(x, 0.5f, vec2(0.5f)).value.x, once);
      sum += once;
    }
  return sum / (kSide * kSide);
}

TEST(DirectLight, AlphaMaskedLeafCastsHalfAShadow) {
  const float sun = 3.0f;
  const Scene scene = test::make_masked_leaf_scene(sun);
  const Accel accel(scene);
  const DirectLight direct(scene, accel);
  const double full = sun / std::numbers::pi;
  EXPECT_NEAR(mean_light_under_leaf(direct), 0.5 * full, 0.01 * full);
  EXPECT_NEAR(direct.one_shadow_ray(receiver({1.5f, 0, 1.5f}, {0, 1, 0}), 0.5f, vec2(0.5f)).value.x,
              full, 1e-5 * full);
}

// glTF BLEND as stochastic transparency: a pane of alpha 0.3 over the floor lets 0.7 of the sun
// through on average; each shadow ray decides by a hash of itself, so the same ray always gets
// the same answer and 4096 rays average to 0.7 within their Bernoulli noise (sd 0.0072).
TEST(DirectLight, AlphaBlendedPaneLetsThroughOneMinusAlpha) {
  const float sun = 3.0f;
  Scene scene = test::make_masked_leaf_scene(sun);
  Material& pane = scene.materials[size_t(scene.meshes[1].material)];
  pane.alpha_mask = false;
  pane.alpha_blend = true;
  pane.alpha_texture = -1;
  pane.alpha_factor = 0.3f;
  const Accel accel(scene);
  const DirectLight direct(scene, accel);
  const double full = sun / std::numbers::pi;
  EXPECT_NEAR(mean_light_under_leaf(direct), 0.7 * full, 0.025 * full);
}

}  // namespace
}  // namespace lb
