// The automatic shadow map size (viewer/shadow_resolution.h): mesh thickness against closed
// forms, and the size it picks for thin and thick casters.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "bake/io/shapes.h"
#include "bake/lights.h"
#include "test_helpers.h"
#include "viewer/shadow_resolution.h"
#include "viewer_test_scenes.h"

namespace lb {
namespace {

constexpr double kPi = 3.14159265358979;

TEST(ShadowResolution, SlabAndRodAreAsThickAsTheirThinnestSide) {
  EXPECT_NEAR(closed_mesh_thickness(make_box({0, 0, 0}, {1.0f, 0.01f, 1.0f})), 0.01f, 1e-6f);
  // A rod's 2 V / A is half its width (0.0098 m here); a ray crosses the width.
  EXPECT_NEAR(closed_mesh_thickness(make_box({0, 0, 0}, {0.02f, 0.5f, 0.02f})), 0.02f, 1e-6f);
}

// A napkin ring, 192-sided: 2 V / A against the polygon's closed form.
TEST(ShadowResolution, ShellThicknessIsTwiceVolumeOverArea) {
  const int n = 192;
  const double outer = 0.1, inner = 0.096, height = 0.05;
  const double annulus = 0.5 * n * std::sin(2.0 * kPi / n) * (outer * outer - inner * inner);
  const double sides = n * 2.0 * std::sin(kPi / n) * (outer + inner) * height;
  const double expected = 2.0 * annulus * height / (sides + 2.0 * annulus);
  const Mesh ring = make_cylinder(float(outer), float(inner), float(height), n, false);
  EXPECT_NEAR(closed_mesh_thickness(ring), expected, 1e-5 * expected);
  EXPECT_NEAR(expected, 0.0037, 0.0001);
}

TEST(ShadowResolution, OpenMeshesHaveNoThickness) {
  EXPECT_TRUE(std::isinf(closed_mesh_thickness(make_quad({1.0f, 1.0f}))));
  Mesh open_box = make_box({0, 0, 0}, {1.0f, 0.01f, 1.0f});
  open_box.triangles.erase(open_box.triangles.begin(), open_box.triangles.begin() + 2);
  EXPECT_TRUE(std::isinf(closed_mesh_thickness(open_box)));
  EXPECT_TRUE(std::isinf(closed_mesh_thickness(Mesh())));
}

TEST(ShadowResolution, NonFiniteMeshHasNoThickness) {
  Mesh box = make_box({0, 0, 0}, {1.0f, 0.01f, 1.0f});
  box.positions[0].x = std::numeric_limits<float>::quiet_NaN();
  EXPECT_TRUE(std::isinf(closed_mesh_thickness(box)));
}

TEST(ShadowResolution, InsideOutBoxHasTheSameThickness) {
  Mesh box = make_box({0, 0, 0}, {1.0f, 0.01f, 1.0f});
  for (uvec3& t : box.triangles) std::swap(t[1], t[2]);
  EXPECT_NEAR(closed_mesh_thickness(box), 0.01f, 1e-6f);
}

// A ring under a 15 cm square light `distance` away along +x (facing it).
Scene ring_and_light(float distance, MaterialKind ring_kind = MaterialKind::diffuse) {
  Scene scene;
  Material white;
  white.name = "white";
  white.kind = ring_kind;
  white.reflectance = vec3(0.8f);
  const int white_id = test::add_material(scene, white);
  Material lamp;
  lamp.name = "lamp";
  lamp.emission = vec3(10.0f);
  const int lamp_id = test::add_material(scene, lamp);
  Mesh ring = make_cylinder(0.1f, 0.096f, 0.05f, 192, false);
  ring.name = "ring";
  ring.material = white_id;
  scene.meshes.push_back(std::move(ring));
  scene.meshes.push_back(test::make_quad({distance, -0.075f, 0.075f}, {0, 0.15f, 0},
                                         {0, 0, -0.15f}, lamp_id, "lamp"));
  return scene;
}

ShadowResolution choose(const Scene& scene, int layers = 6 * 16) {
  return automatic_shadow_resolution(scene, collect_lights(scene), layers);
}

// need = 2 D / (0.8 t), up to a multiple of 256: t = 3.70 mm, so D = 0.5 m needs 338 (the
// minimum, 512), 1.0 m 676 (768), 1.45 m 980 (1024).
TEST(ShadowResolution, ThinRingFarFromItsLightGetsFinerMaps) {
  EXPECT_EQ(choose(ring_and_light(0.5f)).resolution, 512);
  EXPECT_TRUE(choose(ring_and_light(0.5f)).caster.empty());
  const ShadowResolution at_1 = choose(ring_and_light(1.0f));
  EXPECT_EQ(at_1.resolution, 768);
  EXPECT_EQ(at_1.caster, "ring");
  EXPECT_NEAR(at_1.distance, 1.0f, 1e-4f);
  const ShadowResolution at_145 = choose(ring_and_light(1.45f));
  EXPECT_EQ(at_145.resolution, 1024);
  EXPECT_FALSE(at_145.capped);
}

TEST(ShadowResolution, GlassDoesNotAsk) {
  EXPECT_EQ(choose(ring_and_light(1.45f, MaterialKind::glass)).resolution, 512);
}

// 2 m needs 1352 texels; 512 MiB of 32-bit depth affords 16 cubes 1182 (1024 in steps of
// 256), 32 cubes 836 (768) and 200 cubes 334, which the minimum overrides.
TEST(ShadowResolution, MemoryBudgetHoldsTheSize) {
  const Scene scene = ring_and_light(2.0f);
  const ShadowResolution sixteen = choose(scene, 6 * 16);
  EXPECT_EQ(sixteen.resolution, 1024);
  EXPECT_TRUE(sixteen.capped);
  EXPECT_EQ(choose(scene, 6 * 32).resolution, 768);
  const ShadowResolution many = choose(scene, 6 * 200);
  EXPECT_EQ(many.resolution, 512);
  EXPECT_TRUE(many.capped);
}

// The viewer tests' table room (thick table top and legs, a 0.6 m light) keeps 512.
TEST(ShadowResolution, TableRoomKeepsTheMinimum) {
  const ShadowResolution choice = choose(test::make_table_room());
  EXPECT_EQ(choice.resolution, 512);
  EXPECT_TRUE(choice.caster.empty());
}

}  // namespace
}  // namespace lb
