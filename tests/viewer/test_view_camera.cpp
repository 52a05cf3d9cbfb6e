// ViewCamera's limits (issue 15): the orbit's pitch stays within +-89 deg, the eye stops in front
// of the floor and inside a room's walls (ray cast against the scene's Embree accel), and fit
// looks at a closed room from inside. Closed forms for a floor quad; the bundled room for the
// rest.

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "bake/accel.h"
#include "bake/io/scene_load.h"
#include "bake/io/shapes.h"
#include "test_helpers.h"
#include "viewer/view_camera.h"

namespace lb {
namespace {

// A 100 x 100 m floor at y = 0 facing up, nothing else.
Scene floor_scene() {
  Scene scene;
  scene.materials.emplace_back();
  scene.meshes.push_back(make_quad({100.0f, 100.0f}));
  return scene;
}

bool inside(vec3 p, vec3 min, vec3 max) {
  return glm::all(glm::greaterThan(p, min)) && glm::all(glm::lessThan(p, max));
}

TEST(ViewCamera, OrbitPitchStaysWithin89Degrees) {
  ViewCamera camera;
  camera.position = {0.0f, 1.0f, 5.0f};
  orbit(camera, 0.3f, 10.0f);                          // far past the pole
  EXPECT_NEAR(orbit_pitch_deg(camera), 89.0f, 1e-3f);  // measured 89.0000
  EXPECT_LE(orbit_pitch_deg(camera), 89.0f + 1e-4f);
  orbit(camera, 0.0f, -20.0f);
  EXPECT_NEAR(orbit_pitch_deg(camera), -89.0f, 1e-3f);
  EXPECT_GE(orbit_pitch_deg(camera), -89.0f - 1e-4f);
  // The distance is kept: 5.0990 m (sqrt(26)).
  EXPECT_NEAR(glm::length(camera.position - camera.target), std::sqrt(26.0f), 1e-4f);
}

TEST(ViewCamera, OrbitBelowTheFloorStopsInFrontOfItAndComesBack) {
  const Scene scene = floor_scene();
  const Accel accel(scene);
  ViewCamera camera;
  camera.target = {0.0f, 1.0f, 0.0f};
  camera.position = {0.0f, 1.0f, 5.0f};
  // Pitch down 60 deg: without the scene the eye would be at y = 1 - 5 sin 60 = -3.33 m.
  ViewCamera free_camera = camera;
  orbit(free_camera, 0.0f, -glm::radians(60.0f));
  EXPECT_NEAR(free_camera.position.y, 1.0f - 5.0f * std::sin(glm::radians(60.0f)), 1e-4f);
  orbit(camera, 0.0f, -glm::radians(60.0f), &accel);
  // The ray from the target meets the floor at t = 1 / sin 60 = 1.1547 m; the eye stands 2% of
  // that in front of it: y = 1 - 0.98 = 0.02 m.
  EXPECT_NEAR(camera.position.y, 0.02f, 1e-4f);
  EXPECT_NEAR(orbit_pitch_deg(camera), -60.0f, 1e-3f);
  // Back above the floor: the 5 m the orbit had before.
  orbit(camera, 0.0f, glm::radians(80.0f), &accel);
  EXPECT_NEAR(glm::length(camera.position - camera.target), 5.0f, 1e-4f);
  EXPECT_NEAR(orbit_pitch_deg(camera), 20.0f, 1e-3f);
}

TEST(ViewCamera, OrbitAndZoomKeepTheEyeInsideTheRoom) {
  const Scene scene = load_scene(test::source_dir() + "/scenes/room.toml").scene;
  const Accel accel(scene);
  ViewCamera camera;
  camera.target = {0.0f, 1.5f, 0.0f};
  camera.position = {0.0f, 1.5f, 1.5f};
  zoom(camera, 10.0f, &accel);  // 15 m wanted, the wall at z = 2
  EXPECT_GT(camera.position.z, 1.9f);
  EXPECT_LT(camera.position.z, 2.0f);
  std::mt19937 random(7);
  std::uniform_real_distribution<float> step(-0.5f, 0.5f);
  int outside = 0;
  for (int i = 0; i < 500; ++i) {
    orbit(camera, step(random), step(random), &accel);
    if (i % 50 == 0) zoom(camera, 3.0f, &accel);
    if (!inside(camera.position, vec3(-2.0f, 0.0f, -2.0f), vec3(2.0f, 3.0f, 2.0f))) ++outside;
  }
  EXPECT_EQ(outside, 0);
  // The same orbits without the scene leave the room (a check that the test can fail).
  ViewCamera free_camera;
  free_camera.target = {0.0f, 1.5f, 0.0f};
  free_camera.position = {0.0f, 1.5f, 15.0f};
  orbit(free_camera, 0.2f, -0.4f);
  EXPECT_FALSE(inside(free_camera.position, vec3(-2.0f, 0.0f, -2.0f), vec3(2.0f, 3.0f, 2.0f)));
}

TEST(ViewCamera, EnclosureTellsAClosedRoomFromAFloorAndABall) {
  const Scene room = load_scene(test::source_dir() + "/scenes/room.toml").scene;
  const Accel room_accel(room);
  // The room's centre: every direction meets an inward wall (the block and ball are passed or
  // met from outside, which faces the point too).
  EXPECT_EQ(room_enclosure(room_accel, vec3(0.0f, 1.5f, 0.0f)), 1.0f);
  const Scene floor = floor_scene();
  const Accel floor_accel(floor);
  // Above a 100 m floor from 1 m: the lower hemisphere's 64 of 128 directions but its most
  // grazing one (y = -1/128 meets the plane 128 m away, past the floor's 50 m edge).
  EXPECT_EQ(room_enclosure(floor_accel, vec3(0.0f, 1.0f, 0.0f)), 63.0f / 128.0f);
  // Inside a ball (faces out): nothing faces the point.
  Scene ball;
  ball.materials.emplace_back();
  ball.meshes.push_back(make_sphere(1.0f, 16, 32));
  const Accel ball_accel(ball);
  EXPECT_EQ(room_enclosure(ball_accel, vec3(0.0f)), 0.0f);
}

TEST(ViewCamera, FitLooksAtAClosedRoomFromInside) {
  const Scene scene = load_scene(test::source_dir() + "/scenes/room.toml").scene;
  const Accel accel(scene);
  const Bounds bounds = scene_bounds(scene);
  const ViewCamera outside = fit_to_scene(bounds, 50.0f);
  EXPECT_FALSE(inside(outside.position, bounds.min, bounds.max));
  const ViewCamera fitted = fit_to_scene(bounds, 50.0f, &accel);
  EXPECT_TRUE(inside(fitted.position, bounds.min, bounds.max))
      << fitted.position.x << " " << fitted.position.y << " " << fitted.position.z;
  // Against the +z wall (z = 2) by 2% of the 2 m from the centre, at the centre's height,
  // looking at the centre (0, 1.5, 0) along -z.
  EXPECT_NEAR(fitted.position.z, 2.0f - 0.04f, 1e-4f);
  EXPECT_NEAR(fitted.position.x, 0.0f, 1e-6f);
  EXPECT_NEAR(fitted.position.y, 1.5f, 1e-6f);
  EXPECT_NEAR(fitted.target.y, 1.5f, 1e-6f);
  EXPECT_NEAR(fitted.forward().z, -1.0f, 1e-6f);
}

TEST(ViewCamera, FitOfAnOpenSceneIsTheFrontView) {
  const Scene scene = floor_scene();
  const Accel accel(scene);
  const Bounds bounds = scene_bounds(scene);
  const ViewCamera with = fit_to_scene(bounds, 50.0f, &accel);
  const ViewCamera without = fit_to_scene(bounds, 50.0f);
  EXPECT_EQ(with.position, without.position);
  EXPECT_EQ(with.target, without.target);
}

}  // namespace
}  // namespace lb
