#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "bake/accel.h"
#include "bake/sampling.h"
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

// A closed room with a ball and a block: shared edges, curved and flat, blocked and free.
Scene room_with_ball_and_block() {
  Scene scene;
  const int white = test::add_material(scene, Material{});
  scene.meshes.push_back(test::make_box({-2, -2, 0}, {2, 2, 2.5f}, white, true, "room"));
  scene.meshes.push_back(test::make_sphere({0.3f, 0.2f, 1.0f}, 0.5f, 24, 48, white, false));
  scene.meshes.push_back(test::make_box({-1, -1, 0}, {-0.2f, -0.2f, 0.8f}, white, false));
  return scene;
}

// The stream API must find what one ray at a time finds: same hit or miss, same triangle and
// the same bits of t and barycentrics; only an exact tie (a ray through a shared edge) may
// go to the other triangle, at the same distance.
TEST(Accel, IntersectManyFindsWhatIntersectFinds) {
  const Scene scene = room_with_ball_and_block();
  const Accel accel(scene);
  Rng rng(3);
  for (bool coherent : {true, false}) {
    // Coherent: one origin, directions within a small cone; incoherent: anything.
    std::vector<Ray> rays(5000);
    for (Ray& ray : rays) {
      const vec3 d = square_to_cosine_hemisphere(rng.next_2d());
      const vec3 anywhere(3.6f * rng.next_float() - 1.8f, 3.6f * rng.next_float() - 1.8f,
                          0.1f + 2.3f * rng.next_float());
      const float up_or_down = rng.next_float() < 0.5f ? 1.0f : -1.0f;
      ray.origin = coherent ? vec3(0.1f, -0.3f, 2.4f) : anywhere;
      ray.direction = coherent ? glm::normalize(vec3(0.2f * d.x, 0.2f * d.y, -1.0f))
                               : vec3(d.x, d.y, up_or_down * d.z);
    }
    std::vector<std::optional<Hit>> many(rays.size());
    accel.intersect_many(rays.data(), rays.size(), many.data(), coherent);
    size_t hits = 0, ties = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
      const std::optional<Hit> one = accel.intersect(rays[i]);
      ASSERT_EQ(one.has_value(), many[i].has_value()) << i;
      if (!one) continue;
      ++hits;
      if (one->mesh != many[i]->mesh || one->triangle != many[i]->triangle) {
        ++ties;
        EXPECT_NEAR(one->t, many[i]->t, 1e-5f * one->t) << i;
        continue;
      }
      EXPECT_EQ(one->t, many[i]->t) << i;
      EXPECT_EQ(one->barycentric, many[i]->barycentric) << i;
      EXPECT_EQ(one->geometric_normal, many[i]->geometric_normal) << i;
    }
    EXPECT_EQ(hits, rays.size());  // a closed room
    EXPECT_LE(ties, rays.size() / 1000) << (coherent ? "coherent" : "incoherent");
    EXPECT_EQ(accel.intersect_raw_many(rays.data(), rays.size(), coherent), hits);
  }
}

// The stream API's visibility test must answer what occluded() answers on every ray: segments
// from one point to a small patch (coherent) and between random points (incoherent), a mix of
// blocked and free ones.
TEST(Accel, OccludedManyAnswersWhatOccludedAnswers) {
  const Scene scene = room_with_ball_and_block();
  const Accel accel(scene);
  Rng rng(5);
  auto inside = [&] {
    return vec3(3.8f * rng.next_float() - 1.9f, 3.8f * rng.next_float() - 1.9f,
                0.05f + 2.4f * rng.next_float());
  };
  for (bool coherent : {true, false}) {
    std::vector<Ray> rays(5000);
    const vec3 from(0.9f, -0.6f, 0.05f);
    for (Ray& ray : rays) {
      const vec3 a = coherent ? from : inside();
      const vec3 b =
          coherent ? vec3(rng.next_float() - 0.5f, rng.next_float() - 0.5f, 2.45f) : inside();
      ray.origin = a;
      ray.direction = b - a;
      ray.tmax = 1.0f;
    }
    std::unique_ptr<bool[]> blocked(new bool[rays.size()]);
    accel.occluded_many(rays.data(), rays.size(), blocked.get(), coherent);
    size_t blocked_count = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
      ASSERT_EQ(accel.occluded(rays[i]), blocked[i]) << i;
      blocked_count += blocked[i] ? 1 : 0;
    }
    // Both answers occur often enough to mean something (the sphere shadows part of the patch).
    EXPECT_GT(blocked_count, rays.size() / 20) << (coherent ? "coherent" : "incoherent");
    EXPECT_LT(blocked_count, rays.size() - rays.size() / 20)
        << (coherent ? "coherent" : "incoherent");
  }
}

// glTF alphaMode MASK: rays straight down through a leaf whose alpha checker cuts half its
// area hit the floor half the time, through every entry point (intersect, occluded, their
// streams). Before: the leaf was opaque.
TEST(Accel, AlphaMaskLetsRaysThroughTheCutOutHalf) {
  const Scene scene = test::make_masked_leaf_scene(1.0f);
  const Accel accel(scene);
  constexpr int kSide = 64;
  std::vector<Ray> rays;
  for (int i = 0; i < kSide; ++i)
    for (int k = 0; k < kSide; ++k) {
      Ray ray;
      ray.origin = {-0.5f + (float(i) + 0.5f) / kSide, 2.0f, -0.5f + (float(k) + 0.5f) / kSide};
      ray.direction = {0, -1, 0};
      rays.push_back(ray);
    }
  std::vector<Ray> shadows = rays;
  for (Ray& shadow : shadows) shadow.tmax = 1.9f;  // stops above the floor: only the leaf blocks
  std::vector<std::optional<Hit>> hits(rays.size());
  accel.intersect_many(rays.data(), rays.size(), hits.data(), true);
  std::unique_ptr<bool[]> blocked(new bool[rays.size()]);
  accel.occluded_many(shadows.data(), shadows.size(), blocked.get(), false);
  int through = 0;
  for (size_t r = 0; r < rays.size(); ++r) {
    const std::optional<Hit> hit = accel.intersect(rays[r]);
    ASSERT_TRUE(hit && hits[r]);
    EXPECT_EQ(hit->mesh, hits[r]->mesh);
    through += hit->mesh == 0 ? 1 : 0;
    EXPECT_EQ(accel.occluded(shadows[r]), hit->mesh == 1);
    EXPECT_EQ(blocked[r], hit->mesh == 1);
  }
  EXPECT_NEAR(double(through) / double(rays.size()), 0.5, 0.01);
}

}  // namespace
}  // namespace lb
