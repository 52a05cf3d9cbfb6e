#include <gtest/gtest.h>

#include "bake/accel.h"
#include "bake/surface.h"
#include "test_helpers.h"

namespace lb {
namespace {

TEST(Accel, HitsAQuadAtTheRightDistanceAndTriangle) {
  Scene scene;
  const int white = test::add_material(scene, {});
  scene.meshes.push_back(test::make_quad({-1, -1, 0}, {2, 0, 0}, {0, 2, 0}, white));
  const Accel accel(scene);
  Ray ray{{0.25f, -0.5f, 3.0f}, {0, 0, -1}};
  const auto hit = accel.intersect(ray);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->t, 3.0f, 1e-5f);
  EXPECT_EQ(hit->mesh, 0u);
  EXPECT_NEAR(hit->geometric_normal.z, 1.0f, 1e-6f);
  const SurfacePoint sp = surface_at(scene, *hit, ray);
  EXPECT_NEAR(sp.position.x, 0.25f, 1e-5f);
  EXPECT_NEAR(sp.position.y, -0.5f, 1e-5f);
  EXPECT_NEAR(sp.uv.x, 0.625f, 1e-5f);
  EXPECT_NEAR(sp.uv.y, 0.25f, 1e-5f);

  EXPECT_FALSE(accel.intersect(Ray{{5, 5, 3}, {0, 0, -1}}));
  EXPECT_TRUE(accel.occluded(Ray{{0, 0, 3}, {0, 0, -1}}));
  EXPECT_FALSE(accel.occluded(Ray{{0, 0, 3}, {0, 0, -1}, 0.0f, 2.0f}));
}

// Rays leaving a surface must never hit it again, at any distance from the origin.
class OffsetAtScale : public ::testing::TestWithParam<float> {};

TEST_P(OffsetAtScale, SpawnedRaysDoNotSelfIntersect) {
  const float offset = GetParam();
  Scene scene;
  const int white = test::add_material(scene, {});
  const float size = std::max(1.0f, offset * 0.01f);
  // A tilted plane far from the origin: its coordinates carry large rounding errors.
  scene.meshes.push_back(test::make_quad({offset, offset, offset}, {size, 0, 0.3f * size},
                                         {0, size, 0.1f * size}, white));
  const Accel accel(scene);
  int self_hits = 0;
  for (int i = 0; i < 64; ++i)
    for (int j = 0; j < 64; ++j) {
      const vec3 target = vec3(offset) + (float(i) + 0.5f) / 64.0f * vec3(size, 0, 0.3f * size) +
                          (float(j) + 0.5f) / 64.0f * vec3(0, size, 0.1f * size);
      const vec3 n = triangle_normal(scene.meshes[0], 0);
      const Ray primary{target + 2.0f * size * n, -n};
      const auto hit = accel.intersect(primary);
      ASSERT_TRUE(hit);
      const SurfacePoint sp = surface_at(scene, *hit, primary);
      // Leave at a grazing angle, the hardest case, on the front side.
      const vec3 grazing = glm::normalize(vec3(1, 0, 0.3f) + 0.02f * n);
      const vec3 dir = glm::dot(grazing, n) > 0 ? grazing : glm::normalize(grazing + 0.05f * n);
      const Ray bounce{offset_ray_origin(sp.position, sp.geometric_normal, dir), dir};
      self_hits += accel.intersect(bounce).has_value();
    }
  EXPECT_EQ(self_hits, 0);
}

INSTANTIATE_TEST_SUITE_P(Scales, OffsetAtScale, ::testing::Values(0.0f, 1.0f, 100.0f, 1e4f, 1e5f));

}  // namespace
}  // namespace lb
