// The closed-form unshadowed light (unshadowed_light.h) against its limits and against Monte
// Carlo integration over the light, and the direct term's ratio estimator built on it
// (lightmap.h): where nothing blocks the light the map is the closed form's, without noise.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <glm/gtc/constants.hpp>

#include "bake/accel.h"
#include "bake/lightmap/lightmap.h"
#include "bake/lightmap/texel_footprint.h"
#include "bake/lightmap/texel_receiver.h"
#include "bake/lightmap/unshadowed_light.h"
#include "bake/pipeline/bake.h"
#include "bake/sampling.h"
#include "map_read_back.h"
#include "test_helpers.h"

namespace lb {
namespace {

constexpr float kRadiance = 5.0f;  // W/(sr m^2)

// A black floor at y = 0 and a square light of side `size` facing down at `height`.
Scene light_over_floor(float size, float height, bool two_sided) {
  Scene scene;
  Material black;
  black.reflectance = vec3(0.0f);
  Material light = black;
  light.emission = vec3(kRadiance, 0.5f * kRadiance, 0.25f * kRadiance);
  light.two_sided_emission = two_sided;
  const int b = test::add_material(scene, black), l = test::add_material(scene, light);
  scene.meshes.push_back(test::make_quad({-2, 0, 2}, {4, 0, 0}, {0, 0, -4}, b, "floor"));
  scene.meshes.push_back(test::make_quad({-0.5f * size, height, -0.5f * size}, {size, 0, 0},
                                         {0, 0, size}, l, "light"));
  return scene;
}

ReceiverPoint receiver(vec3 position, vec3 normal, vec3 shading) {
  return {position, glm::normalize(normal), glm::normalize(shading)};
}

// The Monte Carlo integral of the same light, 512 x 512 stratified points, no shadow rays.
vec3 monte_carlo(const DirectLight& direct, const ReceiverPoint& x) {
  constexpr int n = 512;
  glm::dvec3 sum(0.0);
  Rng rng(11);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const vec2 u = glm::min(stratified(i, j, n, n, rng.next_2d()), vec2(0.99999994f));
      Ray unused;
      sum += glm::dvec3(direct.sample_one_light(x, 0.5f, u, unused).value);
    }
  return vec3(sum / double(n * n));
}

// A light 200 m square 1 mm above the receiver fills its hemisphere: E = pi L, the map's E/pi
// is L.
TEST(UnshadowedLight, AHugeLightJustAboveFillsTheHemisphere) {
  const Scene scene = light_over_floor(200.0f, 0.001f, false);
  const LightSources sources(scene);
  const vec3 value = unshadowed_direct(scene, sources, receiver({0.3f, 0, 0.2f}, {0, 1, 0}, {0, 1, 0}));
  EXPECT_NEAR(value.x, kRadiance, 1e-4 * kRadiance);
  EXPECT_NEAR(value.z, 0.25f * kRadiance, 1e-4 * kRadiance);
}

// Receivers that see the whole light, part of it over their horizon (a wall beside it, a
// tilted shading normal), and the back of a two-sided light: within 0.1% of Monte Carlo
// (measured: 2e-5 at most).
TEST(UnshadowedLight, MatchesMonteCarloOverTheLight) {
  struct Case {
    bool two_sided;
    ReceiverPoint x;
  };
  const Case cases[] = {
      {false, receiver({0.2f, 0, 0.1f}, {0, 1, 0}, {0, 1, 0})},
      {false, receiver({0.1f, 0.9f, 0.0f}, {-1, 0, 0}, {-1, 0, 0})},   // light across the horizon
      {false, receiver({0.2f, 0, 0.1f}, {0, 1, 0}, {0.5f, 1, 0.2f})},  // bumped normal
      {true, receiver({0.1f, 1.5f, 0.2f}, {0, -1, 0}, {0, -1, 0})},    // above the two-sided light
  };
  for (const Case& c : cases) {
    const Scene scene = light_over_floor(0.6f, 1.0f, c.two_sided);
    const Accel accel(scene);
    const DirectLight direct(scene, accel);
    const LightSources sources(scene);
    const vec3 closed = unshadowed_direct(scene, sources, c.x);
    const vec3 sampled = monte_carlo(direct, c.x);
    ASSERT_GT(sampled.x, 0.0f);
    std::printf("closed form / Monte Carlo: %.5f\n", double(closed.x / sampled.x));
    EXPECT_NEAR(closed.x / sampled.x, 1.0, 0.001)
        << "at (" << c.x.position.x << ", " << c.x.position.y << ", " << c.x.position.z << ")";
  }
  // Behind a one-sided light: nothing.
  const Scene scene = light_over_floor(0.6f, 1.0f, false);
  EXPECT_EQ(unshadowed_direct(scene, LightSources(scene),
                              receiver({0.1f, 1.5f, 0.2f}, {0, -1, 0}, {0, -1, 0}))
                .x,
            0.0f);
}

TEST(UnshadowedLight, APointLampGivesItsExactValue) {
  Scene scene = light_over_floor(0.6f, 1.0f, false);
  scene.meshes.pop_back();
  Lamp lamp;
  lamp.kind = LampKind::point;
  lamp.position = vec3(0.0f, 2.0f, 0.0f);
  lamp.intensity = vec3(3.0f);  // W/sr
  scene.lights.push_back(lamp);
  const vec3 x(1.5f, 0.0f, 0.0f);
  const double d2 = 1.5 * 1.5 + 2.0 * 2.0, cos_x = 2.0 / std::sqrt(d2);
  const vec3 value = unshadowed_direct(scene, LightSources(scene), receiver(x, {0, 1, 0}, {0, 1, 0}));
  EXPECT_NEAR(value.x, 3.0 * cos_x / d2 / glm::pi<double>(), 1e-6);
}

// Where nothing blocks the light the ratio estimator's texels are the tent means of the closed
// form to float rounding (the shadow rays' share is 1 exactly); the plain estimate's noise is
// the control. Under a blocker's umbra both are 0.
TEST(LightmapRatioEstimator, AnOpenFloorUnderAnAreaLightHasNoNoise) {
  Scene scene = light_over_floor(0.6f, 1.0f, false);
  const BakeResult bake = bake_scene(scene, bake_at(10.0f));
  LightmapParams params;
  params.contents = LightmapContents::all;
  params.project_direct = false;  // compare the texels' means with the closed form's
  params.stitch_seams = false;
  params.direct_side = 4;
  const Lightmap ratio = bake_lightmap(scene, bake, params);
  ASSERT_TRUE(ratio.ratio_estimator);
  params.ratio_estimator = false;
  const Lightmap plain = bake_lightmap(scene, bake, params);
  ASSERT_FALSE(plain.ratio_estimator);

  // The closed form's tent means over the points the lightmap integrates it at (half the
  // direct term's side, at least 2).
  std::vector<Mesh> storage;
  const std::vector<const Mesh*> surfaces = lightmap_surfaces(scene, bake, storage);
  const TexelFootprints footprints(surfaces, ratio.width, ratio.height);
  const LightSources sources(scene);
  FillTexelsParams fill;
  fill.rule = FootprintRule::stratified;
  fill.side = 2;
  fill.seed = hash_seed(params.seed, 0xd12ec7);
  fill.plane_fit_at_borders = false;
  const std::vector<vec3> exact = fill_texels(
      footprints,
      [&](std::span<const FootprintSample> samples, std::span<vec3> values, size_t) {
        for (size_t s = 0; s < samples.size(); ++s)
          values[s] = unshadowed_direct(scene, sources,
                                        receiver_at_sample(*surfaces[samples[s].mesh], samples[s]));
      },
      fill);
  double worst_ratio = 0.0, plain_rms = 0.0;
  size_t floor_texels = 0;
  for (size_t k = 0; k < exact.size(); ++k) {
    if (!(exact[k].x > 0.05f * kRadiance)) continue;  // the floor's lit nodes
    worst_ratio = std::max(worst_ratio, std::abs(double(ratio.direct_term[k].x) / exact[k].x - 1));
    plain_rms += std::pow(double(plain.direct_term[k].x) / exact[k].x - 1, 2);
    ++floor_texels;
  }
  ASSERT_GT(floor_texels, 100u);
  plain_rms = std::sqrt(plain_rms / double(floor_texels));
  std::printf("ratio estimator: worst %.3g off the closed form; plain: %.3g rms\n", worst_ratio,
              plain_rms);
  EXPECT_LE(worst_ratio, 1e-5);
  EXPECT_GE(plain_rms, 1e-3) << "the plain estimate has no noise here: a weak control";
}

}  // namespace
}  // namespace lb
