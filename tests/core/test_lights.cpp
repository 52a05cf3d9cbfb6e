#include <gtest/gtest.h>
#include <glm/gtc/constants.hpp>

#include "bake/lights.h"
#include "bake/sampling.h"
#include "test_helpers.h"

namespace lb {
namespace {

TEST(Lights, PowerOfALambertianQuadIsPiRadianceArea) {
  Scene scene;
  Material lamp;
  lamp.emission = vec3(2.0f, 1.0f, 0.5f);
  const int lamp_id = test::add_material(scene, lamp);
  const int white = test::add_material(scene, {});
  scene.meshes.push_back(test::make_quad({0, 0, 0}, {2, 0, 0}, {0, 0.5f, 0}, lamp_id, "lamp"));
  scene.meshes.push_back(test::make_quad({0, 0, -1}, {1, 0, 0}, {0, 1, 0}, white, "floor"));
  const auto lights = collect_lights(scene);
  ASSERT_EQ(lights.size(), 1u);
  EXPECT_FLOAT_EQ(lights[0].area, 1.0f);
  EXPECT_NEAR(lights[0].power.x, 2.0f * glm::pi<float>(), 1e-5f);
  EXPECT_NEAR(lights[0].power.z, 0.5f * glm::pi<float>(), 1e-5f);
  EXPECT_NEAR(lights[0].normal.z, 1.0f, 1e-6f);
  EXPECT_NEAR(lights[0].centroid.x, 1.0f, 1e-6f);
  EXPECT_NEAR(lights[0].centroid.y, 0.25f, 1e-6f);
}

TEST(Lights, SamplesCoverTheLightUniformly) {
  Scene scene;
  Material lamp;
  lamp.emission = vec3(1.0f);
  const int lamp_id = test::add_material(scene, lamp);
  scene.meshes.push_back(test::make_quad({0, 0, 0}, {3, 0, 0}, {0, 1, 0}, lamp_id));
  const auto lights = collect_lights(scene);
  Rng rng(11);
  glm::dvec3 mean(0.0);
  const int n = 50000;
  int left_third = 0;
  for (int i = 0; i < n; ++i) {
    const LightSample s = lights[0].sample(scene, rng.next_2d());
    mean += glm::dvec3(s.position);
    left_third += s.position.x < 1.0f;
    EXPECT_FLOAT_EQ(s.pdf_area, 1.0f / 3.0f);
  }
  mean /= double(n);
  EXPECT_NEAR(mean.x, 1.5, 0.02);
  EXPECT_NEAR(mean.y, 0.5, 0.01);
  EXPECT_NEAR(double(left_third) / n, 1.0 / 3.0, 0.01);
}

}  // namespace
}  // namespace lb
