#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "bake/light_sources.h"
#include "bake/sampling.h"
#include "test_helpers.h"

namespace lb {
namespace {

constexpr double kPi = std::numbers::pi;

Scene floor_scene() {
  Scene scene;
  const int white = test::add_material(scene, {});
  scene.meshes.push_back(test::make_quad({-1, 0, -1}, {2, 0, 0}, {0, 0, 2}, white, "floor"));
  return scene;
}

Lamp spot(float inner, float outer) {
  Lamp lamp;
  lamp.kind = LampKind::spot;
  lamp.position = {0, 2, 0};
  lamp.direction = {0, -1, 0};
  lamp.intensity = vec3(3.0f, 2.0f, 1.0f);
  lamp.inner_cone = inner;
  lamp.outer_cone = outer;
  return lamp;
}

TEST(LightSources, SpotFalloffFollowsGltf) {
  const Lamp lamp = spot(0.2f, 0.6f);
  EXPECT_FLOAT_EQ(spot_falloff(lamp, std::cos(0.1f)), 1.0f);
  EXPECT_FLOAT_EQ(spot_falloff(lamp, std::cos(0.7f)), 0.0f);
  const float c = 0.5f * (std::cos(0.2f) + std::cos(0.6f));
  EXPECT_NEAR(spot_falloff(lamp, c), 0.25f, 1e-5f);  // half way in cos: (1/2)^2
}

TEST(LightSources, RangeWindowIsOneNearAndZeroBeyond) {
  Lamp lamp;
  lamp.range = 10.0f;
  EXPECT_NEAR(range_window(lamp, 1.0f), std::pow(1.0f - 1e-4f, 2.0f), 1e-6f);
  EXPECT_FLOAT_EQ(range_window(lamp, 10.0f), 0.0f);
  EXPECT_FLOAT_EQ(range_window(lamp, 20.0f), 0.0f);
  lamp.range = 0.0f;
  EXPECT_FLOAT_EQ(range_window(lamp, 1e6f), 1.0f);
}

// The mean power of emitted rays is the light's power, which for a spot is its intensity
// integrated over the cone's falloff (closed form in lamp_power, checked here by quadrature).
TEST(LightSources, EmittedRaysCarryTheLightsPower) {
  Scene scene = floor_scene();
  scene.lights.push_back(spot(0.3f, 0.8f));
  Lamp point;
  point.position = {0, 1, 0};
  point.intensity = vec3(1.0f);
  scene.lights.push_back(point);
  const LightSources lights(scene);
  ASSERT_EQ(lights.size(), 2u);
  EXPECT_EQ(lights.kind(0), LightKind::spot);
  EXPECT_NEAR(lights.power(1).x, 4.0 * kPi, 1e-5);

  // Quadrature of the falloff over the cone: 2 pi int f(cos) dcos.
  double quadrature = 0.0;
  const int steps = 200000;
  for (int i = 0; i < steps; ++i) {
    const double c = -1.0 + 2.0 * (i + 0.5) / steps;
    quadrature += spot_falloff(scene.lights[0], float(c)) * 2.0 / steps;
  }
  quadrature *= 2.0 * kPi;
  EXPECT_NEAR(lights.power(0).x / 3.0, quadrature, 1e-4 * quadrature);

  for (size_t light = 0; light < lights.size(); ++light) {
    glm::dvec3 sum(0.0);
    const int n = 64;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        const EmittedRay ray =
            lights.emit(light, {0.5f, 0.5f}, stratified(i, j, n, n, {0.5f, 0.5f}));
        EXPECT_NEAR(glm::length(ray.direction), 1.0f, 1e-5f);
        sum += glm::dvec3(ray.power);
      }
    sum /= double(n * n);
    EXPECT_NEAR(sum.x / lights.power(light).x, 1.0, 2e-3) << "light " << light;
  }
}

TEST(LightSources, PointLampGivesInverseSquareIrradiance) {
  Scene scene = floor_scene();
  Lamp lamp;
  lamp.position = {0, 2, 0};
  lamp.intensity = vec3(5.0f);
  scene.lights.push_back(lamp);
  const LightSources lights(scene);
  const LightTowards t = lights.sample_towards(0, {0, 0, 0}, {0.5f, 0.5f});
  EXPECT_TRUE(t.delta);
  EXPECT_FLOAT_EQ(t.distance, 2.0f);
  EXPECT_FLOAT_EQ(t.radiance.x, 5.0f / 4.0f);
  EXPECT_FLOAT_EQ(t.direction.y, 1.0f);
}

// Directional rays start outside the scene, travel along the light and cross the scene's
// bounding disk: their power sums to irradiance times the disk's area.
TEST(LightSources, DirectionalRaysCoverTheScene) {
  Scene scene = floor_scene();
  Lamp sun;
  sun.kind = LampKind::directional;
  sun.direction = glm::normalize(vec3(0.3f, -1.0f, 0.2f));
  sun.intensity = vec3(2.0f);
  scene.lights.push_back(sun);
  const LightSources lights(scene);
  const BoundingSphere& b = lights.bounds();
  EXPECT_NEAR(lights.power(0).x, 2.0 * kPi * b.radius * b.radius, 1e-4);
  for (vec2 u : {vec2(0.0f), vec2(0.99f, 0.5f), vec2(0.5f, 0.5f)}) {
    const EmittedRay ray = lights.emit(0, u, {0.5f, 0.5f});
    EXPECT_EQ(ray.direction, sun.direction);
    // Upstream of the centre by the radius, within the radius sideways.
    const vec3 offset = ray.origin - b.centre;
    EXPECT_NEAR(glm::dot(offset, sun.direction), -b.radius, 1e-4f);
    EXPECT_LE(glm::length(offset - glm::dot(offset, sun.direction) * sun.direction),
              b.radius * 1.0001f);
  }
}

TEST(SkyLight, EquirectRoundTrip) {
  for (vec3 d : {vec3(0, 0, -1), vec3(1, 0, 0), glm::normalize(vec3(0.3f, 0.8f, 0.2f)),
                 glm::normalize(vec3(-0.5f, -0.4f, 0.7f))}) {
    const vec3 back = equirect_to_direction(direction_to_equirect(d));
    EXPECT_NEAR(glm::length(back - d), 0.0f, 1e-5f);
  }
  EXPECT_NEAR(direction_to_equirect({0, 0, -1}).x, 0.5f, 1e-6f);  // -Z at the image centre
  EXPECT_NEAR(direction_to_equirect({0, 1, 0}).y, 0.0f, 1e-6f);   // zenith on the top row
}

// Drawing directions in proportion to an image's luminance: the density returned matches
// pdf(direction), and radiance / pdf averages to the image's integral over the sphere.
TEST(SkyLight, ImageSamplingIsConsistent) {
  const Texture image = test::make_rgb_texture(16, 8, [](int i, int j) {
    const float bright = (i == 5 && j == 2) ? 40.0f : 1.0f + 0.1f * float(j);
    return vec3(bright, 0.5f * bright, 0.25f);
  });
  Sky sky;
  sky.radiance = vec3(2.0f);
  const SkyLight light(sky, &image);
  // Closed form of the integral: sum of texel radiance times texel solid angle.
  double expected = 0.0;
  for (int j = 0; j < image.height; ++j) {
    const double omega =
        2.0 * kPi / image.width *
        (std::cos(kPi * j / image.height) - std::cos(kPi * (j + 1) / image.height));
    for (int i = 0; i < image.width; ++i)
      expected += 2.0 * image.texels[size_t((j * image.width + i) * 3)] * omega;
  }
  EXPECT_NEAR(light.integral().x, expected, 1e-4 * expected);

  Rng rng(3);
  glm::dvec3 estimate(0.0);
  const int n = 200000;
  for (int k = 0; k < n; ++k) {
    float pdf = 0.0f;
    const vec3 d = light.sample(rng.next_2d(), pdf);
    ASSERT_GT(pdf, 0.0f);
    EXPECT_NEAR(light.pdf(d) / pdf, 1.0f, 1e-3f);
    estimate += glm::dvec3(light.radiance(d)) / double(pdf);
  }
  estimate /= double(n);
  EXPECT_NEAR(estimate.x / light.integral().x, 1.0, 0.01);
  EXPECT_NEAR(estimate.z / light.integral().z, 1.0, 0.01);  // a channel the pdf ignores
}

TEST(SkyLight, ConstantSkyIsUniform) {
  Scene scene = floor_scene();
  scene.sky = Sky{vec3(1.5f), -1};
  const LightSources lights(scene);
  ASSERT_EQ(lights.size(), 1u);
  EXPECT_EQ(lights.kind(0), LightKind::sky);
  const float r = lights.bounds().radius;
  EXPECT_NEAR(lights.power(0).x, 1.5 * 4.0 * kPi * kPi * r * r, 1e-3);
  const LightTowards t = lights.sample_towards(0, {0, 0, 0}, {0.2f, 0.7f});
  EXPECT_FLOAT_EQ(t.pdf, float(1.0 / (4.0 * kPi)));
  EXPECT_TRUE(std::isinf(t.distance));
}

// A double-sided emitter (glTF doubleSided) lights both faces: twice one face's power in the
// light list, Lambert's irradiance seen from either side, half the rays leaving from the back.
// Before: one face's power, nothing above the panel, every ray downwards.
TEST(LightSources, DoubleSidedEmitterLightsBothFacesWithTwiceThePower) {
  const float size = 0.5f, radiance = 4.0f;
  const test::TwoSidedPanel two = test::make_two_sided_panel(size, radiance, 1.0f, 0.5f);
  const test::TwoSidedPanel one = test::make_two_sided_panel(size, radiance, 1.0f, 0.5f, false);
  const double one_face = kPi * radiance * size * size;
  const LightSources lights(two.scene);
  ASSERT_EQ(lights.size(), 1u);
  EXPECT_NEAR(lights.power(0).x, 2.0 * one_face, 1e-5 * one_face);
  EXPECT_NEAR(collect_lights(two.scene)[0].power.y, 2.0 * one_face, 1e-5 * one_face);
  EXPECT_NEAR(LightSources(one.scene).power(0).z, one_face, 1e-5 * one_face);

  constexpr int kSide = 256;
  for (const float y : {0.4f, -0.4f}) {
    const vec3 p(0.1f, y, 0.05f), n(0.0f, y > 0.0f ? -1.0f : 1.0f, 0.0f);
    Rng rng(5);
    double sum = 0.0;
    for (int i = 0; i < kSide; ++i)
      for (int k = 0; k < kSide; ++k) {
        const LightTowards t = lights.sample_towards(0, p, stratified(i, k, kSide, kSide,
                                                                      rng.next_2d()));
        if (t.pdf > 0.0f) sum += t.radiance.x * std::max(glm::dot(n, t.direction), 0.0f) / t.pdf;
      }
    const double exact =
        test::polygon_irradiance(two.corners, glm::dvec3(p), glm::dvec3(n), radiance);
    EXPECT_NEAR(sum / (kSide * kSide), exact, 0.005 * exact) << "y " << y;
  }

  Rng rng(6);
  int up = 0;
  double power = 0.0;
  constexpr int kRays = 20000;
  for (int k = 0; k < kRays; ++k) {
    const EmittedRay ray = lights.emit(0, rng.next_2d(), rng.next_2d());
    up += ray.direction.y > 0.0f ? 1 : 0;
    power += ray.power.x;
  }
  EXPECT_NEAR(double(up) / kRays, 0.5, 0.02);
  EXPECT_NEAR(power / kRays, 2.0 * one_face, 1e-4 * one_face);
}

}  // namespace
}  // namespace lb
