// The viewer's stochastic direct light (shaders/light_pick.glsl, Renderer::render): no light
// cap, the estimate's running mean converging to the full evaluation, the band refinement
// reaching the full frame's bits, and the same bits for the same frames.
//
// The scene: 100 small emitting quads (10 x 10, 0.1 m, 0.4 m apart) 2 m above a white floor,
// facing it, and a box on the floor that shadows part of it; the camera under the lights.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "test_helpers.h"
#include "viewer/offscreen_context.h"
#include "viewer/renderer.h"
#include "viewer/snapshot.h"
#include "viewer_test_scenes.h"

namespace lb {
namespace {

constexpr int kWidth = 160, kHeight = 120;
constexpr float kRho = 0.5f;
constexpr double kPi = std::numbers::pi;
constexpr float kLightSize = 0.1f, kLightHeight = 2.0f;

Scene hundred_lights(bool box) {
  Scene scene;
  scene.source_path = "hundred lights (in code)";
  Material white;
  white.reflectance = vec3(kRho);
  const int floor = test::add_material(scene, white);
  scene.meshes.push_back(test::make_quad({-4, 0, -4}, {0, 0, 8}, {8, 0, 0}, floor, "floor"));
  if (box) {
    Material grey;
    grey.reflectance = vec3(0.5f);
    scene.meshes.push_back(test::make_box({-0.3f, 0.0f, -0.3f}, {0.3f, 0.8f, 0.3f},
                                          test::add_material(scene, grey), false, "box"));
  }
  for (int i = 0; i < 10; ++i) {
    for (int j = 0; j < 10; ++j) {
      Material lamp;
      lamp.reflectance = vec3(0.0f);
      // Radiance 10..19.9 W/(sr m^2), slightly coloured, different per light.
      lamp.emission = vec3(10.0f + float(i), 12.0f, 10.0f + 0.99f * float(j));
      const vec3 corner(-1.8f + 0.4f * float(i), kLightHeight, -1.8f + 0.4f * float(j));
      // Front along cross(+x, +z) = -y: facing the floor.
      scene.meshes.push_back(test::make_quad(corner, {kLightSize, 0, 0}, {0, 0, kLightSize},
                                             test::add_material(scene, lamp), "light"));
    }
  }
  Camera camera;
  camera.position = {0.0f, 1.6f, 2.6f};
  camera.target = {0.0f, 0.0f, 0.0f};
  camera.vertical_fov_deg = 60.0f;
  scene.cameras.push_back(camera);
  return scene;
}

RenderSettings direct_settings(DirectMode mode, int refine_bands) {
  RenderSettings settings;
  settings.term = Term::direct;
  settings.direct_mode = mode;
  settings.refine_bands = refine_bands;
  return settings;
}

// Radiance of `frames` still frames, rendered by a renderer of its own.
Image render_frames(const Scene& scene, const RenderSettings& settings, int frames) {
  OffscreenContext context;
  Renderer renderer;
  renderer.set_scene(scene, nullptr);
  const ViewCamera camera = choose_camera(scene, "");
  for (int f = 0; f < frames; ++f) renderer.render(camera, kWidth, kHeight, settings);
  return renderer.read_radiance();
}

// 100 area lights (more than the 32 the uniform arrays held) render, and every floor pixel is
// rho times the sum of the 100 closed forms (Lambert, in double, test::polygon_irradiance /
// pi). Measured worst relative error 3.1e-4 (the shader's float against double: small lights
// 2 m away subtend small angles).
TEST(ViewerStochastic, HundredAreaLightsMatchTheClosedForms) {
  const Scene scene = hundred_lights(false);
  SnapshotOptions options;
  options.width = kWidth;
  options.height = kHeight;
  options.settings = direct_settings(DirectMode::full, 0);
  const Image image = render_snapshot(scene, nullptr, options);
  const ViewCamera camera = choose_camera(scene, "");
  double worst = 0.0;
  int pixels = 0;
  for (int y = 0; y < kHeight; y += 3) {
    for (int x = 0; x < kWidth; x += 3) {
      const Ray ray = test::camera_ray(camera, kWidth, kHeight, x, y);
      if (ray.direction.y >= -1e-3f) continue;
      const glm::dvec3 p = glm::dvec3(ray.origin) -
                           double(ray.origin.y / ray.direction.y) * glm::dvec3(ray.direction);
      if (std::abs(p.x) > 3.9 || std::abs(p.z) > 3.9) continue;
      glm::dvec3 expected(0.0);
      for (const Mesh& mesh : scene.meshes) {
        const Material& m = scene.materials[size_t(mesh.material)];
        if (!m.is_emitter()) continue;
        std::vector<glm::dvec3> polygon(mesh.positions.begin(), mesh.positions.end());
        for (int k = 0; k < 3; ++k) {
          expected[k] +=
              kRho * test::polygon_irradiance(polygon, p, {0, 1, 0}, double(m.emission[k])) / kPi;
        }
      }
      for (int k = 0; k < 3; ++k)
        worst = std::max(worst, std::abs(double(image.at(x, y, k)) - expected[k]) / expected[k]);
      ++pixels;
    }
  }
  std::printf("100 area lights: worst relative error %.2e over %d floor pixels\n", worst, pixels);
  EXPECT_GT(pixels, 1000);
  EXPECT_LT(worst, 1e-3);
}

// The estimate's running mean (refine_bands 0) converges to the full evaluation: the largest
// display difference (lb::max_display_difference, 1/255 = one 8-bit step) over all pixels,
// measured 161.4/255 after 1 frame, 27.8/255 after 16, 10.2/255 after 64: the worst pixel
// (a penumbra pixel on the box's edge) falls between 1/N and 1/sqrt(N).
TEST(ViewerStochastic, RunningMeanConvergesToTheFullEvaluation) {
  const Scene scene = hundred_lights(true);
  const ToneMap tone;
  const Image full = render_frames(scene, direct_settings(DirectMode::full, 0), 1);
  const RenderSettings stochastic = direct_settings(DirectMode::stochastic, 0);
  const double d1 = max_display_difference(render_frames(scene, stochastic, 1), full, tone);
  const double d16 = max_display_difference(render_frames(scene, stochastic, 16), full, tone);
  const double d64 = max_display_difference(render_frames(scene, stochastic, 64), full, tone);
  std::printf(
      "running mean: max display difference %.2f/255 after 1, %.2f/255 after 16, "
      "%.2f/255 after 64 frames\n",
      255.0 * d1, 255.0 * d16, 255.0 * d64);
  EXPECT_GT(d1, 4.0 / 255.0);  // one frame is a noisy estimate, not the full image
  EXPECT_LT(d16, d1 / 4.0);
  EXPECT_LT(d64, d16 / 2.0);
  EXPECT_LT(d64, 14.0 / 255.0);
}

// With refine_bands B the still frames 2..B+1 replace the estimate by the full evaluation, so
// frame B+1 is the full frame bit for bit, and a later render() keeps it.
TEST(ViewerStochastic, RefinedStillFrameIsTheFullFrame) {
  const Scene scene = hundred_lights(true);
  const Image full = render_frames(scene, direct_settings(DirectMode::full, 0), 1);
  const RenderSettings stochastic = direct_settings(DirectMode::stochastic, 4);
  EXPECT_NE(render_frames(scene, stochastic, 4).pixels, full.pixels);  // one band left
  EXPECT_EQ(render_frames(scene, stochastic, 5).pixels, full.pixels);
  EXPECT_EQ(render_frames(scene, stochastic, 9).pixels, full.pixels);
}

// The random numbers are a hash of pixel and frame: the same frames give the same bits, and
// another frame count another image.
TEST(ViewerStochastic, SameFramesSameBits) {
  const Scene scene = hundred_lights(true);
  const RenderSettings stochastic = direct_settings(DirectMode::stochastic, 0);
  const Image a = render_frames(scene, stochastic, 3);
  const Image b = render_frames(scene, stochastic, 3);
  EXPECT_EQ(a.pixels, b.pixels);
  EXPECT_NE(render_frames(scene, stochastic, 2).pixels, a.pixels);
}

}  // namespace
}  // namespace lb
