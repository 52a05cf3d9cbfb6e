// The viewer's direct term against ray tracing, on a Figure 6-like room with a table.
//
// 1. Unshadowed: the closed-form polygon irradiance (shaders/lights.glsl) against 32x32
//    stratified light samples per pixel. Both estimate the same integral; the difference is
//    Monte Carlo noise (~0.3%) plus rasteriser/ray disagreement on silhouette pixels.
// 2. Shadowed: the shadow cubes against shadow rays. The cubes see the light from K points,
//    so penumbrae are made of K steps and edges move by up to a shadow-map texel; the
//    metric allows for that (stated in the assertions).
// 3. Contact: Figure 3's thin ring on a floor under a grazing lamp, against shadow rays.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "bake/io/image_io.h"
#include "bake/io/shapes.h"
#include "test_helpers.h"
#include "viewer/offscreen_context.h"
#include "viewer/renderer.h"
#include "viewer/shadow_maps.h"
#include "viewer/snapshot.h"
#include "viewer_test_scenes.h"

namespace lb {
namespace {

constexpr int kWidth = 160, kHeight = 120;

struct Agreement {
  double mean_relative = 0.0;     // mean over lit pixels of |gl - ref| / ref (luminance)
  double fraction_over_10 = 0.0;  // fraction of lit pixels with relative error > 10%
  size_t lit_pixels = 0;
};

float luminance(const Image& image, int x, int y) {
  return 0.2126f * image.at(x, y, 0) + 0.7152f * image.at(x, y, 1) + 0.0722f * image.at(x, y, 2);
}

// Lit pixels: reference above 2% of the image's mean, so relative errors are meaningful.
Agreement agreement(const Image& gl, const Image& ref) {
  double mean = 0.0;
  for (int y = 0; y < ref.height; ++y)
    for (int x = 0; x < ref.width; ++x) mean += luminance(ref, x, y);
  mean /= double(ref.width * ref.height);
  Agreement result;
  double sum = 0.0;
  size_t over = 0;
  for (int y = 0; y < ref.height; ++y) {
    for (int x = 0; x < ref.width; ++x) {
      const double r = luminance(ref, x, y);
      if (r < 0.02 * mean) continue;
      const double e = std::abs(double(luminance(gl, x, y)) - r) / r;
      sum += e;
      over += e > 0.10 ? 1 : 0;
      ++result.lit_pixels;
    }
  }
  result.mean_relative = sum / double(std::max<size_t>(result.lit_pixels, 1));
  result.fraction_over_10 = double(over) / double(std::max<size_t>(result.lit_pixels, 1));
  return result;
}

Image render_direct(const Scene& scene, bool shadows, int pixel_samples = 1, int scale = 1,
                    int shadow_resolution = 512, ShadowResolution* chosen = nullptr) {
  SnapshotOptions options;
  options.width = kWidth * scale;
  options.height = kHeight * scale;
  options.pixel_samples = pixel_samples;
  options.settings.term = Term::direct;
  options.settings.shadows = shadows;
  options.shadows.samples_per_light = 16;
  options.shadows.resolution = shadow_resolution;
  return render_snapshot(scene, nullptr, options, chosen);
}

TEST(ViewerDirect, UnshadowedClosedFormMatchesMonteCarlo) {
  const Scene scene = test::make_table_room();
  const ViewCamera camera = choose_camera(scene, "");
  const Image gl = render_direct(scene, false);
  const Image ref = test::ray_traced_direct(scene, camera, kWidth, kHeight, 32, false);
  const Agreement a = agreement(gl, ref);
  if (a.mean_relative > 0.01 || a.fraction_over_10 > 0.01)
    test::write_comparison_files("viewer_direct_unshadowed", gl, ref);
  EXPECT_GT(a.lit_pixels, size_t(kWidth * kHeight / 2));
  EXPECT_LT(a.mean_relative, 0.01);     // 1% mean relative error
  EXPECT_LT(a.fraction_over_10, 0.01);  // under 1% of pixels (silhouettes) off by > 10%
  std::printf("unshadowed: mean relative %.4f, over 10%% %.4f of %zu lit pixels\n", a.mean_relative,
              a.fraction_over_10, a.lit_pixels);
}

TEST(ViewerDirect, ShadowedMatchesShadowRays) {
  const Scene scene = test::make_table_room();
  const ViewCamera camera = choose_camera(scene, "");
  const Image gl = render_direct(scene, true);
  const Image ref = test::ray_traced_direct(scene, camera, kWidth, kHeight, 16, true);
  const Agreement a = agreement(gl, ref);
  if (a.mean_relative > 0.03 || a.fraction_over_10 > 0.05)
    test::write_comparison_files("viewer_direct_shadowed", gl, ref);
  EXPECT_GT(a.lit_pixels, size_t(kWidth * kHeight / 2));
  EXPECT_LT(a.mean_relative, 0.03);     // 3% mean relative error
  EXPECT_LT(a.fraction_over_10, 0.05);  // under 5% of pixels (penumbra steps, edges) > 10%
  std::printf("shadowed: mean relative %.4f, over 10%% %.4f of %zu lit pixels\n", a.mean_relative,
              a.fraction_over_10, a.lit_pixels);
}

// A double-sided emitter (glTF doubleSided) lights the floor above it as well: the viewer's
// closed form, light lists and shadow cubes against shadow-ray tracing, seen from between the
// panel and the upper floor. Before: the upper floor was black in the viewer.
TEST(ViewerDirect, DoubleSidedEmitterLightsTheFloorAbove) {
  test::TwoSidedPanel panel = test::make_two_sided_panel(0.5f, 10.0f, 0.5f, 0.5f);
  Camera camera;
  camera.position = vec3(0.0f, 0.1f, 1.2f);
  camera.target = vec3(0.0f, 0.5f, 0.0f);
  camera.vertical_fov_deg = 60.0f;
  panel.scene.cameras.push_back(camera);
  const ViewCamera view = choose_camera(panel.scene, "");
  const Image gl = render_direct(panel.scene, true);
  const Image ref = test::ray_traced_direct(panel.scene, view, kWidth, kHeight, 16, true);
  const Agreement a = agreement(gl, ref);
  if (a.mean_relative > 0.03 || a.fraction_over_10 > 0.05)
    test::write_comparison_files("viewer_direct_double_sided", gl, ref);
  EXPECT_GT(a.lit_pixels, size_t(kWidth * kHeight / 4));
  EXPECT_LT(a.mean_relative, 0.03);
  EXPECT_LT(a.fraction_over_10, 0.05);
  std::printf("double-sided: mean relative %.4f, over 10%% %.4f of %zu lit pixels\n",
              a.mean_relative, a.fraction_over_10, a.lit_pixels);
}

// A smaller light gives a sharper shadow: the penumbra of the table leg shadows shrinks. Count
// pixels whose direct term lies strictly between umbra and full light.
TEST(ViewerDirect, PenumbraFollowsLightSize) {
  auto penumbra_pixels = [](float light_size) {
    Scene scene = test::make_table_room(light_size);
    // Keep the light's power equal so the images are comparable.
    scene.materials[2].emission *= (0.6f * 0.6f) / (light_size * light_size);
    const Image lit = render_direct(scene, false);
    const Image shadowed = render_direct(scene, true);
    int count = 0;
    for (int y = 0; y < lit.height; ++y) {
      for (int x = 0; x < lit.width; ++x) {
        const float full = luminance(lit, x, y);
        if (full <= 0.0f) continue;
        const float v = luminance(shadowed, x, y) / full;
        count += (v > 0.05f && v < 0.95f) ? 1 : 0;
      }
    }
    return count;
  };
  const int small = penumbra_pixels(0.15f);
  const int large = penumbra_pixels(1.2f);
  std::printf("penumbra pixels: light 0.15 m -> %d, 1.2 m -> %d\n", small, large);
  EXPECT_GT(large, 2 * small);
}

// `--pixel-samples 2` is a 2 x 2 box filter: the same sample points as an image twice the size,
// averaged over each 2 x 2 block (what the reference integrates over a pixel, one sample a
// sub-pixel), to float rounding and the odd edge sample that the shifted projection puts on
// the other side of a triangle edge. Unshadowed: with shadows each sub-pixel frame also has its
// own shadow points (test_viewer_penumbra.cpp).
TEST(ViewerDirect, PixelSamplesAreABoxFilterOfTheFinerImage) {
  const Scene scene = test::make_table_room();
  const Image filtered = render_direct(scene, false, 2);
  const Image fine = render_direct(scene, false, 1, 2);
  const Image centre = render_direct(scene, false, 1);
  double sum_filtered = 0.0, sum_box = 0.0, sum_centre = 0.0, worst_mean = 0.0;
  size_t off = 0, centre_off = 0;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const double box =
          0.25 * (double(luminance(fine, 2 * x, 2 * y)) + luminance(fine, 2 * x + 1, 2 * y) +
                  luminance(fine, 2 * x, 2 * y + 1) + luminance(fine, 2 * x + 1, 2 * y + 1));
      const double f = luminance(filtered, x, y), c = luminance(centre, x, y);
      const double scale = std::max(box, 1e-3);
      off += std::abs(f - box) > 1e-4 * scale ? 1 : 0;
      centre_off += std::abs(c - box) > 1e-4 * scale ? 1 : 0;
      worst_mean += std::abs(f - box) / scale;
      sum_filtered += f;
      sum_box += box;
      sum_centre += c;
    }
  }
  const double pixels = double(kWidth * kHeight);
  worst_mean /= pixels;
  std::printf(
      "box filter: %zu of %d pixels off by > 1e-4 (centre samples: %zu), mean %.2e, "
      "sums %.6f / %.6f (centre %.6f)\n",
      off, kWidth * kHeight, centre_off, worst_mean, sum_filtered, sum_box, sum_centre);
  EXPECT_LT(double(off), 0.002 * pixels);          // measured 18 of 19200 (edge samples)
  EXPECT_LT(worst_mean, 5e-4);                     // measured 1.77e-4, all from those 18
  EXPECT_NEAR(sum_filtered / sum_box, 1.0, 2e-4);  // measured 1 + 2.7e-5
  EXPECT_GT(double(centre_off), 0.02 * pixels);    // the centre samples are not: measured 734
}

// Figure 3's napkin ring (5 cm tall, 4 mm wall, 0.5 mm above the floor; diffuse here) under
// its 15 cm lamp 35 degrees up, and a camera on the far side looking at the ring's shadow.
// The lamp sees the ring's side walls edge-on, where a slope-scaled depth bias is largest,
// and the floor at their foot lies in shadow within millimetres of its caster.
Scene make_ring_on_floor() {
  Scene scene;
  scene.source_path = "ring_on_floor (in code)";
  Material cloth;
  cloth.name = "cloth";
  cloth.reflectance = vec3(0.8f);
  const int cloth_id = test::add_material(scene, cloth);
  Material lamp;
  lamp.name = "lamp";
  lamp.reflectance = vec3(0.0f);
  lamp.emission = vec3(100.0f);
  const int lamp_id = test::add_material(scene, lamp);
  scene.meshes.push_back(
      test::make_quad({-0.5f, 0, -0.5f}, {0, 0, 1}, {1, 0, 0}, cloth_id, "floor"));
  Mesh ring = make_cylinder(0.1f, 0.096f, 0.05f, 192, false);
  for (vec3& p : ring.positions) p.y += 0.0255f;
  ring.name = "ring";
  ring.material = cloth_id;
  scene.meshes.push_back(std::move(ring));
  // Facing the ring: cross(u, v) = n for u along z and v = n x u.
  const vec3 n = glm::normalize(vec3(-1.2f, -0.85f, 0.0f));
  const vec3 u(0.0f, 0.0f, 0.15f);
  const vec3 v = glm::cross(n, u);
  scene.meshes.push_back(
      test::make_quad(vec3(1.2f, 0.87f, 0.0f) - 0.5f * (u + v), u, v, lamp_id, "lamp"));
  Camera camera;
  camera.name = "shadow side";
  camera.position = {-0.45f, 0.55f, 0.0f};
  camera.target = {-0.04f, 0.0f, -0.09f};  // the wall's foot where the lamp sees it edge-on
  camera.vertical_fov_deg = 12.0f;
  scene.cameras.push_back(camera);
  return scene;
}

// The floor at the ring's foot on the shadow side: its direct term against 16 x 16 shadow
// rays a pixel, as the L1 error over the image relative to the reference's sum (dark pixels
// count: that is where a leak shows). At 512 texels, measured: 0.0144 with the lookup moved
// along the light ray (shadows.glsl); 0.022 with the normal offset before it, 0.026 with a
// fixed half-texel receiver lift, 0.052 with the shadow pass's slope bias at 2 (the foot lit
// where the lamp sees the wall edge-on). The bounds sit between the last two measurements.
// A failure (over `bound`) writes the images.
constexpr double kContactBoundAt512 = 0.018;
constexpr double kContactBoundAutomatic = 0.010;  // measured 0.0076, below (0.0137 before)

double contact_error(int shadow_resolution, const char* name, double bound,
                     ShadowResolution* chosen = nullptr) {
  const Scene scene = make_ring_on_floor();
  const ViewCamera camera = choose_camera(scene, "");
  const Image gl = render_direct(scene, true, 1, 1, shadow_resolution, chosen);
  const Image ref = test::ray_traced_direct(scene, camera, kWidth, kHeight, 16, true);
  double error = 0.0, sum = 0.0, gl_sum = 0.0;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      error += std::abs(double(luminance(gl, x, y)) - luminance(ref, x, y));
      sum += luminance(ref, x, y);
      gl_sum += luminance(gl, x, y);
    }
  }
  const double relative = error / sum;
  if (relative > bound || std::getenv("LIGHTBAKE_WRITE_COMPARISONS"))
    test::write_comparison_files(name, gl, ref);
  std::printf("contact at %d texels: L1 error / sum %.4f, sum ratio %.4f\n", shadow_resolution,
              relative, gl_sum / sum);
  EXPECT_GT(sum, 0.0);
  return relative;
}

TEST(ViewerDirect, ThinWallShadowsTheFloorAtItsFoot) {
  EXPECT_LT(contact_error(512, "viewer_direct_contact", kContactBoundAt512),
            kContactBoundAt512);
}

// The automatic size (viewer/shadow_resolution.h) picks the ring, 3.7 mm thick 1.45 m from
// the lamp, and the light leaking along its foot halves: measured L1 error 0.0223 -> 0.0137,
// sum ratio 1.0208 -> 1.0108 (shadow rays: 1), with the normal offset; with the lookup moved
// along the light ray 0.0144 -> 0.0076, sum ratio 1.0120 -> 1.0031.
TEST(ViewerDirect, AutomaticShadowSizeFollowsTheThinWall) {
  ShadowResolution chosen;
  const double automatic = contact_error(0, "viewer_direct_contact_automatic",
                                         kContactBoundAutomatic, &chosen);
  EXPECT_EQ(chosen.caster, "ring");
  EXPECT_NEAR(chosen.thickness, 0.0037f, 0.0001f);
  EXPECT_EQ(chosen.resolution, 1024);
  EXPECT_FALSE(chosen.capped);
  EXPECT_LT(automatic, kContactBoundAutomatic);
  EXPECT_LT(automatic, 0.8 * contact_error(512, "viewer_direct_contact", kContactBoundAt512));
}

// The ring scene's lamp copied to `count` lamps in a grid above it.
Scene ring_with_lamps(int count) {
  Scene scene = make_ring_on_floor();
  const Mesh lamp = scene.meshes.back();
  for (int i = 1; i < count; ++i) {
    Mesh copy = lamp;
    for (vec3& p : copy.positions) p.z += 0.2f * float(i % 7) - 0.6f, p.y += 0.1f * float(i / 7);
    scene.meshes.push_back(std::move(copy));
  }
  return scene;
}

// 200 lights at the automatic K (2 points each, at least) would need 2400 layers, over
// llvmpipe's 2048: the automatic K goes down to one point a light instead (until 3 Dec 2026
// such a level did not render at all). 16-texel faces keep the test's memory small.
TEST(ViewerDirect, ManyLightsGetFewerShadowPointsNotNone) {
  const Scene scene = ring_with_lamps(200);
  OffscreenContext context;
  ShadowSettings shadows;
  shadows.resolution = 16;
  ASSERT_LT(max_shadow_layers(), 6 * 2 * 200) << "this OpenGL holds 2 points a light";
  Renderer renderer;
  renderer.set_scene(scene, nullptr, shadows);
  EXPECT_EQ(renderer.stats().shadow_cubes, 200);
  EXPECT_EQ(shadow_samples_per_light(shadows, 200, max_shadow_layers()), 1);
  EXPECT_EQ(shadow_samples_per_light(shadows, 200), 2);  // without the limit
  EXPECT_EQ(shadow_samples_per_light(shadows, 3, 2048), 8);  // 24 / 3, within the limit
}

// More shadow cubes than a depth texture array can have layers: 43 lights x 16 points x 6
// faces = 4128 layers, over llvmpipe's 2048 (and any driver's 4096). The snapshot fails at
// once with the size and what to lower, before allocating anything; before, the texture call
// failed quietly and the render stopped later at an unrelated step ("uploading the light
// lists: OpenGL error 0x0501").
TEST(ViewerDirect, TooManyShadowCubesFailWithTheirSize) {
  const Scene scene = ring_with_lamps(43);
  try {
    render_direct(scene, true, 1, 1, 16);
    FAIL() << "rendered 4128 shadow layers";
  } catch (const std::runtime_error& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("4128 faces of 16^2 texels"), std::string::npos) << message;
    EXPECT_NE(message.find("layers this OpenGL allows"), std::string::npos) << message;
    EXPECT_NE(message.find("--shadow-samples"), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace lb
