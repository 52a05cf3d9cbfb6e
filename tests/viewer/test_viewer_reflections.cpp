// Planar reflections stay bounded (viewer/renderer.h, kMaxPlanarPasses): coplanar mirrors share
// one pass and draw what one mirror of their union draws, at most kMaxPlanarPasses planes get a
// pass per frame, planes out of view get none, and rough glossy plates never get one.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "test_helpers.h"
#include "viewer/offscreen_context.h"
#include "viewer/renderer.h"
#include "viewer_test_scenes.h"

namespace lb {
namespace {

constexpr int kWidth = 160, kHeight = 120;

int add_mirror(Scene& scene) {
  Material mirror;
  mirror.name = "mirror";
  mirror.kind = MaterialKind::mirror;
  mirror.reflectance = vec3(0.9f);
  return test::add_material(scene, mirror);
}

// The table room with a 3 x 3 m mirror on the floor, 2 cm up (no depth fight with the floor): one mesh, or `tiles` x `tiles`
// coplanar meshes covering the same square.
Scene room_with_mirror_floor(int tiles) {
  Scene scene = test::make_table_room();
  const int mirror = add_mirror(scene);
  const float size = 3.0f / float(tiles);
  for (int i = 0; i < tiles; ++i)
    for (int k = 0; k < tiles; ++k)
      // Faces up: cross(+z, +x) = +y.
      scene.meshes.push_back(
          test::make_quad({-1.5f + size * float(i), 0.02f, -1.5f + size * float(k)}, {0, 0, size},
                          {size, 0, 0}, mirror, "floor tile"));
  return scene;
}

Image render(Renderer& renderer, const Scene& scene, const ViewCamera& camera) {
  renderer.set_scene(scene, nullptr);
  renderer.render(camera, kWidth, kHeight, RenderSettings{});
  return renderer.read_radiance();
}

TEST(ViewerReflections, CoplanarMirrorsShareOnePassAndDrawAsOne) {
  OffscreenContext context;
  Renderer renderer;
  const Scene whole = room_with_mirror_floor(1);
  const Scene tiled = room_with_mirror_floor(4);
  const ViewCamera camera = ViewCamera::from(whole.cameras[0]);
  const Image one = render(renderer, whole, camera);
  EXPECT_EQ(renderer.stats().planar_planes, 1);
  EXPECT_EQ(renderer.stats().planar_passes, 1);
  const Image sixteen = render(renderer, tiled, camera);
  EXPECT_EQ(renderer.stats().planar_planes, 1) << "16 coplanar tiles are one plane";
  EXPECT_EQ(renderer.stats().planar_passes, 1);
  double sum = 0.0, difference = 0.0;
  for (size_t i = 0; i < one.pixels.size(); ++i) {
    sum += std::abs(one.pixels[i]);
    difference += std::abs(one.pixels[i] - sixteen.pixels[i]);
  }
  test::write_comparison_files("mirror_floor_tiles", sixteen, one);
  std::printf("one mirror vs 16 tiles: mean |difference| %.3g of the mean value\n",
              difference / sum);
  EXPECT_GT(sum, 0.0);
  // Only the tiles' shared edges may rasterise differently (measured 0 here).
  EXPECT_LT(difference / sum, 1e-3);
}

// 17 flat glossy plates (the Blender scene that froze the window) get at most
// kMaxPlanarPasses passes a frame; rough plates none; planes out of view none.
TEST(ViewerReflections, AtMostAFewPassesAFrameAndNoneForRoughOrUnseenPlates) {
  Scene scene = test::make_table_room();
  Material smooth;
  smooth.name = "smooth plate";
  smooth.kind = MaterialKind::glossy;
  smooth.reflectance = vec3(0.8f);
  smooth.roughness = 0.1f;
  const int smooth_id = test::add_material(scene, smooth);
  Material rough = smooth;
  rough.name = "rough plate";
  rough.roughness = 0.8f;
  const int rough_id = test::add_material(scene, rough);
  // Plates on the back wall (z = -1.99), each 0.2 m in its own plane, facing +z.
  for (int i = 0; i < 17; ++i) {
    const float z = -1.99f + 0.01f * float(i);
    scene.meshes.push_back(test::make_quad({-1.8f + 0.21f * float(i), 1.0f, z}, {0.2f, 0, 0},
                                           {0, 0.2f, 0}, smooth_id, "plate"));
  }
  scene.meshes.push_back(
      test::make_quad({-1.0f, 2.0f, -1.8f}, {0.5f, 0, 0}, {0, 0.5f, 0}, rough_id, "rough"));
  OffscreenContext context;
  Renderer renderer;
  renderer.set_scene(scene, nullptr);
  EXPECT_EQ(renderer.stats().planar_planes, 17) << "the rough plate gets no plane";
  ViewCamera camera = ViewCamera::from(scene.cameras[0]);
  camera.position = {0.0f, 1.5f, 1.9f};
  camera.target = {0.0f, 1.1f, -2.0f};
  renderer.render(camera, kWidth, kHeight, RenderSettings{});
  EXPECT_EQ(renderer.stats().planar_passes, kMaxPlanarPasses);
  // Looking away from the wall: every plate is behind the camera.
  camera.target = {0.0f, 1.1f, 4.0f};
  renderer.render(camera, kWidth, kHeight, RenderSettings{});
  EXPECT_EQ(renderer.stats().planar_passes, 0);
}

}  // namespace
}  // namespace lb
