// The sky as the viewer's background (shaders/sky.frag): where a pixel's ray meets no surface
// it shows the sky's radiance in that direction, lb::SkyLight::radiance (the bake's own lookup,
// an independent CPU implementation), and surfaces cover it.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "bake/accel.h"
#include "bake/sky_light.h"
#include "test_helpers.h"
#include "viewer/snapshot.h"
#include "viewer_test_scenes.h"

namespace lb {
namespace {

constexpr int kWidth = 128, kHeight = 96;

// A floor at y = 0 and a camera at 1 m looking along it: the upper half of the view is sky.
Scene sky_floor(const Sky& sky) {
  Scene scene;
  scene.source_path = "sky floor (in code)";
  Material white;
  white.reflectance = vec3(0.8f);
  const int id = test::add_material(scene, white);
  scene.meshes.push_back(test::make_quad({-8, 0, -8}, {0, 0, 16}, {16, 0, 0}, id, "floor"));
  scene.sky = sky;
  Camera camera;
  camera.position = {0.0f, 1.0f, 5.0f};
  camera.target = {0.5f, 1.5f, 0.0f};
  camera.vertical_fov_deg = 90.0f;
  scene.cameras.push_back(camera);
  return scene;
}

struct SkyCheck {
  int sky_pixels = 0, mismatched = 0;  // sky pixels off the CPU lookup by more than 1e-6 relative
  int floor_pixels = 0, floor_showing_sky = 0;
};

SkyCheck check(const Scene& scene, Term term) {
  SnapshotOptions options;
  options.width = kWidth;
  options.height = kHeight;
  options.settings.term = term;
  const Image image = render_snapshot(scene, nullptr, options);
  const Texture* texture =
      scene.sky->texture >= 0 ? &scene.textures[size_t(scene.sky->texture)] : nullptr;
  const SkyLight sky(*scene.sky, texture);
  const Accel accel(scene);
  const ViewCamera view = choose_camera(scene, "");
  SkyCheck result;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const Ray ray = test::camera_ray(view, kWidth, kHeight, x, y);
      const vec3 got(image.at(x, y, 0), image.at(x, y, 1), image.at(x, y, 2));
      if (accel.intersect(ray)) {
        ++result.floor_pixels;
        const vec3 s = sky.radiance(ray.direction);
        result.floor_showing_sky += (got == s) ? 1 : 0;
        continue;
      }
      const vec3 expected = sky.radiance(ray.direction);
      ++result.sky_pixels;
      const float error = glm::length(got - expected) / glm::length(expected);
      result.mismatched += error > 1e-6f ? 1 : 0;
    }
  }
  return result;
}

TEST(ViewerSky, ConstantSkyFillsTheBackground) {
  Sky sky;
  sky.radiance = {0.3f, 0.5f, 0.9f};
  const SkyCheck c = check(sky_floor(sky), Term::all);
  std::printf("constant sky: %d of %d sky pixels off, %d of %d floor pixels show the sky\n",
              c.mismatched, c.sky_pixels, c.floor_showing_sky, c.floor_pixels);
  EXPECT_GT(c.sky_pixels, kWidth * kHeight / 3);
  EXPECT_GT(c.floor_pixels, kWidth * kHeight / 4);
  EXPECT_EQ(c.mismatched, 0);
  EXPECT_EQ(c.floor_showing_sky, 0);
}

TEST(ViewerSky, EquirectSkyMatchesSkyLightLookup) {
  Scene scene = sky_floor(Sky{});
  // 16 x 8 texels, each a different colour, so a wrong column or row shows.
  Texture image;
  image.path = "sky (in code)";
  image.width = 16;
  image.height = 8;
  image.channels = 3;
  for (int j = 0; j < image.height; ++j) {
    for (int i = 0; i < image.width; ++i) {
      image.texels.push_back(0.1f + 0.05f * float(i));
      image.texels.push_back(0.2f + 0.1f * float(j));
      image.texels.push_back(0.5f + 0.03f * float((i * 7 + j * 3) % 16));
    }
  }
  scene.textures.push_back(image);
  scene.sky = Sky{vec3(2.0f, 1.5f, 1.0f), 0};
  const SkyCheck c = check(scene, Term::all);
  std::printf("equirect sky: %d of %d sky pixels off the CPU lookup\n", c.mismatched, c.sky_pixels);
  EXPECT_GT(c.sky_pixels, kWidth * kHeight / 3);
  // Pixels whose direction lies within float rounding of a texel border may pick the
  // neighbour: allow 1% of them.
  EXPECT_LE(c.mismatched, c.sky_pixels / 100);
}

// A planar mirror floor shows the sky through its mirrored pass: reflectance times the sky.
TEST(ViewerSky, PlanarMirrorReflectsTheSky) {
  Sky sky;
  sky.radiance = {0.3f, 0.5f, 0.9f};
  Scene scene = sky_floor(sky);
  scene.materials[0].kind = MaterialKind::mirror;
  scene.materials[0].reflectance = vec3(0.9f);
  SnapshotOptions options;
  options.width = kWidth;
  options.height = kHeight;
  const Image image = render_snapshot(scene, nullptr, options);
  const Accel accel(scene);
  const ViewCamera view = choose_camera(scene, "");
  double worst = 0.0;
  int mirror_pixels = 0;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      if (!accel.intersect(test::camera_ray(view, kWidth, kHeight, x, y))) continue;
      for (int c = 0; c < 3; ++c) {
        const double expected = 0.9 * sky.radiance[c];
        worst = std::max(worst, std::abs(image.at(x, y, c) - expected) / expected);
      }
      ++mirror_pixels;
    }
  }
  std::printf("mirror: worst relative error %.2e over %d pixels\n", worst, mirror_pixels);
  EXPECT_GT(mirror_pixels, kWidth * kHeight / 4);
  EXPECT_LT(worst, 1e-3);  // the mirrored pass is stored as half floats (RGBA16F)
}

// Debug outputs of light terms show no sky (it is not one of their terms).
TEST(ViewerSky, DirectTermShowsNoSky) {
  Sky sky;
  sky.radiance = vec3(1.0f);
  const SkyCheck c = check(sky_floor(sky), Term::direct);
  EXPECT_EQ(c.mismatched, c.sky_pixels);
}

}  // namespace
}  // namespace lb
