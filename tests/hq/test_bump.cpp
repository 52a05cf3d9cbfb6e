// Bump mapping for the direct-light cosine: height map (Blinn) and tangent-space normal map.

#include <gtest/gtest.h>

#include "bake/bump.h"
#include "test_helpers.h"

namespace lb {
namespace {

Scene bumped_quad(Texture texture, BumpKind kind, float scale) {
  Scene scene;
  scene.textures.push_back(std::move(texture));
  Material material;
  material.bump = kind;
  material.bump_texture = 0;
  material.bump_scale = scale;
  const int index = test::add_material(scene, material);
  // 1 x 1 m facing +z with uv = (x, y): dp/du = +x, dp/dv = +y.
  scene.meshes.push_back(test::make_quad({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, index));
  return scene;
}

SurfacePoint centre_of(const Scene& scene) {
  SurfacePoint sp;
  sp.mesh = 0;
  sp.triangle = 0;
  sp.uv = {0.5f, 0.25f};
  sp.geometric_normal = sp.shading_normal = {0, 0, 1};
  sp.material = &scene.materials[0];
  return sp;
}

// A height ramp h = u (metres per unit, times bump_scale s) tilts the normal to (-s, 0, 1)/|.|.
TEST(Bump, HeightRampTiltsNormalAnalytically) {
  Texture ramp;
  ramp.width = 64;
  ramp.height = 4;
  ramp.channels = 1;
  for (int j = 0; j < ramp.height; ++j)
    for (int i = 0; i < ramp.width; ++i) ramp.texels.push_back((float(i) + 0.5f) / 64.0f);
  const float s = 0.5f;
  const Scene scene = bumped_quad(ramp, BumpKind::height, s);
  const vec3 n = bumped_normal(scene, centre_of(scene));
  const vec3 expected = glm::normalize(vec3(-s, 0, 1));
  EXPECT_NEAR(glm::length(n - expected), 0.0f, 1e-4f);
}

// A constant tangent-space normal (0.5, 0, 1) (texel (0.75, 0.5, 1)) on a quad whose tangent is
// +x gives the world normal (0.5, 0, 1)/|.|; bump_scale scales x and y.
TEST(Bump, NormalMapUsesUvTangentFrame) {
  Texture map;
  map.width = map.height = 1;
  map.channels = 3;
  map.texels = {0.75f, 0.5f, 1.0f};
  const Scene scene = bumped_quad(map, BumpKind::normal_map, 1.0f);
  EXPECT_NEAR(
      glm::length(bumped_normal(scene, centre_of(scene)) - glm::normalize(vec3(0.5f, 0, 1))), 0.0f,
      1e-5f);
  const Scene half = bumped_quad(map, BumpKind::normal_map, 0.5f);
  EXPECT_NEAR(glm::length(bumped_normal(half, centre_of(half)) - glm::normalize(vec3(0.25f, 0, 1))),
              0.0f, 1e-5f);
}

TEST(Bump, NoBumpKeepsShadingNormal) {
  Scene scene;
  test::add_material(scene, Material{});
  scene.meshes.push_back(test::make_quad({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 0));
  const SurfacePoint sp = centre_of(scene);
  EXPECT_EQ(bumped_normal(scene, sp), sp.shading_normal);
}

}  // namespace
}  // namespace lb
