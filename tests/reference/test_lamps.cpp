// Point, spot and directional lamps and a sky in HQ mode (direct term only) and in the
// reference, against the closed forms of issue 14: a white floor lit by one lamp, seen from
// straight above. HQ's soft light comes from the bake, so HQ renders with its direct term only
// (HqParams illumination_map = radiosity = false): a single floor plane has no bounce light
// anyway, and the reference, rendering everything, must give the same values.

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstring>
#include <numbers>
#include <string>
#include <vector>

#include "bake/hq/hq_render.h"
#include "bake/reference/reference.h"
#include "hq_scenes.h"
#include "lamp_scenes.h"
#include "reference_test_support.h"
#include "test_helpers.h"

namespace lb {
namespace {

using test::FloorComparison;

constexpr double kPi = std::numbers::pi;
constexpr int kSize = 33;  // odd: the centre pixel looks straight down the axis

enum class Renderer { hq, reference };

std::string name_of(Renderer r) {
  return r == Renderer::hq ? "hq" : "reference";
}

// The image (grey per pixel, row 0 at the top): HQ's direct term with 4 x 4 samples per pixel,
// or the reference with 64 passes (one lamp: both are exact per sample on a lone floor, only
// the jitter over the pixel varies).
std::vector<double> render_grey(Renderer renderer, const Scene& scene, const Camera& camera,
                                int passes = 64) {
  std::vector<vec3> image;
  if (renderer == Renderer::hq) {
    const BakedScene baked = test::unbaked(scene);
    HqParams params;
    params.width = params.height = kSize;
    params.samples_per_side = 4;
    params.illumination_map = false;
    params.radiosity = false;
    const HqRenderer hq(baked, params);
    HqStats stats;
    image = hq.render(camera, 1, stats);
  } else {
    reference::ReferenceParams params;
    params.width = params.height = kSize;
    params.spp = passes;
    image = reference::render(scene, camera, params).average();
  }
  std::vector<double> grey;
  for (const vec3& v : image) grey.push_back(reference::grey(v));
  return grey;
}

double radial(glm::dvec3 p) {
  return std::hypot(p.x, p.z);
}

class Lamps : public testing::TestWithParam<Renderer> {};

// A point lamp of I W/sr at height h over a floor of reflectance rho: rho I / (pi h^2) right
// below it (1%), rho I h / (pi (h^2 + r^2)^(3/2)) at distance r (2%).
TEST_P(Lamps, PointLampGivesTheInverseSquareCosineCubedFalloff) {
  const float rho = 0.5f, intensity = 3.0f, h = 1.2f;
  Camera camera;
  Scene scene = test::make_lamp_floor(rho, 3.0f, 3.0f, 1.5f, camera);
  scene.lights.push_back(test::point_lamp({0.0f, h, 0.0f}, intensity));
  const std::vector<double> image = render_grey(GetParam(), scene, camera);
  const double below = image[size_t(kSize / 2 * kSize + kSize / 2)];
  const double expected_below = rho * intensity / (kPi * h * h);
  EXPECT_NEAR(below / expected_below, 1.0, 0.01) << below << " vs " << expected_below;
  auto closed_form = [&](glm::dvec3 p) {
    return test::point_lamp_radiance(rho, intensity, h, radial(p));
  };
  const FloorComparison c =
      test::compare_floor([&](int x, int y) { return image[size_t(y * kSize + x)]; }, camera, kSize,
                          kSize, closed_form, [](glm::dvec3) { return true; });
  EXPECT_EQ(c.pixels, kSize * kSize);
  EXPECT_LT(c.worst, 0.02);
  RecordProperty("point", "below " + std::to_string(below / expected_below - 1.0) + " worst " +
                              std::to_string(c.worst));
  std::printf("[%s] point: below %.6f (closed form %.6f, %+.4f%%), worst pixel %.4f%%\n",
              name_of(GetParam()).c_str(), below, expected_below,
              100.0 * (below / expected_below - 1.0), 100.0 * c.worst);
}

// A spot (inner cone 20 degrees, outer 28.6): the point lamp's values inside its inner cone,
// exactly 0 outside its outer cone.
TEST_P(Lamps, SpotLampIsThePointLampInsideItsInnerConeAndDarkOutside) {
  const float rho = 0.7f, intensity = 2.0f, h = 1.2f, inner = 0.35f, outer = 0.5f;
  Camera camera;
  Scene scene = test::make_lamp_floor(rho, 3.0f, 3.0f, 1.5f, camera);
  scene.lights.push_back(test::spot_lamp({0.0f, h, 0.0f}, intensity, inner, outer));
  const std::vector<double> image = render_grey(GetParam(), scene, camera);
  const double inner_radius = h * std::tan(double(inner)),
               outer_radius = h * std::tan(double(outer));
  const FloorComparison c = test::compare_floor(
      [&](int x, int y) { return image[size_t(y * kSize + x)]; }, camera, kSize, kSize,
      [&](glm::dvec3 p) {
        return radial(p) < inner_radius ? test::point_lamp_radiance(rho, intensity, h, radial(p))
                                        : 0.0;
      },
      [&](glm::dvec3 p) { return radial(p) < inner_radius || radial(p) > outer_radius; });
  EXPECT_GT(c.pixels, 50);
  EXPECT_GT(c.zero_pixels, 600);
  EXPECT_LT(c.worst, 0.02);
  EXPECT_EQ(c.worst_zero, 0.0);
  const double below = image[size_t(kSize / 2 * kSize + kSize / 2)];
  EXPECT_NEAR(below / (rho * intensity / (kPi * h * h)), 1.0, 0.01);
  std::printf("[%s] spot: %d pixels inside, worst %.4f%%; %d outside, largest %.3g\n",
              name_of(GetParam()).c_str(), c.pixels, 100.0 * c.worst, c.zero_pixels, c.worst_zero);
}

// A directional lamp of E W/m^2 at 30 degrees from the vertical: rho E cos / pi wherever the
// floor sees it, 0 in the shadow of a black 0.6 m square at 0.5 m (and on the square itself).
TEST_P(Lamps, DirectionalLampLightsEverythingUnshadowedEqually) {
  const float rho = 0.6f, irradiance = 2.0f;
  const double theta = kPi / 6.0;
  Camera camera;
  Scene scene = test::make_lamp_floor(rho, 3.0f, 3.0f, 1.5f, camera);
  Material black;
  black.reflectance = vec3(0.0f);
  const int black_material = test::add_material(scene, black);
  // Occluder: x in [-0.8, -0.2], z in [-0.3, 0.3], y = 0.5, facing up.
  scene.meshes.push_back(test::make_quad({-0.8f, 0.5f, 0.3f}, {0.6f, 0, 0}, {0, 0, -0.6f},
                                         black_material, "occluder"));
  scene.lights.push_back(
      test::directional_lamp({float(std::sin(theta)), -float(std::cos(theta)), 0.0f}, irradiance));
  const std::vector<double> image = render_grey(GetParam(), scene, camera);
  // Floor point p is in shadow when p + s (-sin, cos, 0) crosses the square (s = 0.5 / cos), and
  // hidden when the camera's line to it does (at 5/6 of the way from the camera at y = 3).
  auto shadowed = [&](glm::dvec3 p) {
    const double x = p.x - 0.5 * std::tan(theta);
    return x > -0.8 && x < -0.2 && std::abs(p.z) < 0.3;
  };
  auto hidden = [](glm::dvec3 p) {
    const double x = p.x * 5.0 / 6.0, z = p.z * 5.0 / 6.0;
    return x > -0.8 && x < -0.2 && std::abs(z) < 0.3;
  };
  const double lit_value = rho * irradiance * std::cos(theta) / kPi;
  auto pixel = [&](int x, int y) { return image[size_t(y * kSize + x)]; };
  const FloorComparison lit = test::compare_floor(
      pixel, camera, kSize, kSize, [&](glm::dvec3) { return lit_value; },
      [&](glm::dvec3 p) { return !shadowed(p) && !hidden(p); });
  const FloorComparison dark = test::compare_floor(
      pixel, camera, kSize, kSize, [](glm::dvec3) { return 0.0; },
      [&](glm::dvec3 p) { return shadowed(p) || hidden(p); });
  EXPECT_GT(lit.pixels, 800);
  EXPECT_GT(dark.zero_pixels, 40);
  EXPECT_LT(lit.worst, 1e-4);  // a constant: float rounding only
  EXPECT_EQ(dark.worst_zero, 0.0);
  std::printf("[%s] directional: %d lit pixels, worst %.2g; %d dark, largest %.3g\n",
              name_of(GetParam()).c_str(), lit.pixels, lit.worst, dark.zero_pixels,
              dark.worst_zero);
}

// ---- The sky ---------------------------------------------------------------------------------
// A constant sky L over a 2 x 2 m floor with nothing above it: the reference gives rho L on
// the floor (first bounce only: the floor cannot see itself) and L where the camera looks past
// the floor.
TEST(ReferenceSky, ConstantSkyOverAnOpenFloorIsRhoL) {
  const float rho = 0.5f, sky = 1.5f;
  Camera camera;
  Scene scene = test::make_lamp_floor(rho, 1.0f, 3.0f, 1.5f, camera);
  scene.sky = Sky{vec3(sky), -1};
  reference::ReferenceParams params;
  params.width = params.height = kSize;
  params.spp = 64;
  const reference::Film film = reference::render(scene, camera, params);
  const std::vector<vec3> image = film.average();
  const std::vector<vec3> half0 = film.half_average(0), half1 = film.half_average(1);
  auto pixel = [&](int x, int y) { return reference::grey(image[size_t(y * kSize + x)]); };
  auto on_floor = [](glm::dvec3 p) { return std::abs(p.x) < 1.0 && std::abs(p.z) < 1.0; };
  const auto one = [](glm::dvec3) { return 1.0; };
  const double expected = double(rho) * sky;
  int floor_pixels = 0, sky_pixels = 0;
  double floor_sum = 0.0, worst_floor = 0.0, squares = 0.0, variance = 0.0, worst_sky = 0.0;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const size_t i = size_t(y * kSize + x);
      if (test::floor_pixel(camera, kSize, kSize, x, y, one, on_floor).kept) {
        const double error = pixel(x, y) / expected - 1.0;
        floor_sum += pixel(x, y);
        worst_floor = std::max(worst_floor, std::abs(error));
        squares += error * error;
        // The halves' difference: the variance of this pixel's mean (film.h).
        const double d = (reference::grey(half0[i]) - reference::grey(half1[i])) / expected;
        variance += d * d / 4.0;
        ++floor_pixels;
      } else if (test::floor_pixel(camera, kSize, kSize, x, y, one, [&](glm::dvec3 p) {
                   return !on_floor(p);
                 }).kept) {
        worst_sky = std::max(worst_sky, std::abs(pixel(x, y) / sky - 1.0));
        ++sky_pixels;
      }
    }
  ASSERT_GT(floor_pixels, 400);
  ASSERT_GT(sky_pixels, 200);
  const double floor_mean = floor_sum / floor_pixels / expected - 1.0;
  // The floor's own per-pixel relative standard error, from the halves; its mean's is that
  // over sqrt(pixels). Tolerances: the mean within 4 of its standard errors, every pixel within
  // 5 (the largest of ~440 normal errors is ~3 of them).
  const double pixel_se = std::sqrt(variance / floor_pixels);
  EXPECT_LT(std::abs(floor_mean), 4.0 * pixel_se / std::sqrt(double(floor_pixels)));
  EXPECT_LT(worst_floor, 5.0 * pixel_se);
  EXPECT_LT(worst_sky, 1e-6);  // seen straight: exact
  std::printf(
      "[reference] sky: floor mean %+.4f%% (per-pixel standard error %.3f%%, %d pixels), "
      "worst floor pixel %.3f%%, RMS %.3f%%; sky pixels worst %.2g\n",
      100.0 * floor_mean, 100.0 * pixel_se, floor_pixels, 100.0 * worst_floor,
      100.0 * std::sqrt(squares / floor_pixels), worst_sky);
}

// An equirect sky (16 x 8 texels, a 40x bright texel 45-67 degrees from the zenith) over the
// same floor: next-event estimation draws texels by luminance and the floor's scattered rays
// that escape are weighted against it (power heuristic). The floor's radiance is
// rho / pi * sum over the upper rows' texels of L dphi (sin^2 theta1 - sin^2 theta0) / 2
// (the cosine-weighted solid angle of each texel; rows 0-3 are exactly the upper hemisphere).
TEST(ReferenceSky, EquirectSkyOverAnOpenFloorMatchesItsTexelSum) {
  const float rho = 0.5f;
  Camera camera;
  Scene scene = test::make_lamp_floor(rho, 1.0f, 3.0f, 0.9f, camera);
  const Texture image = test::make_rgb_texture(16, 8, [](int i, int j) {
    return vec3((i == 5 && j == 2) ? 40.0f : 1.0f + 0.1f * float(j));
  });
  scene.textures.push_back(image);
  scene.sky = Sky{vec3(0.5f), 0};
  double expected = 0.0;
  for (int j = 0; j < image.height / 2; ++j) {
    const double s0 = std::sin(kPi * j / image.height), s1 = std::sin(kPi * (j + 1) / image.height);
    for (int i = 0; i < image.width; ++i)
      expected += 0.5 * double(image.texels[size_t((j * image.width + i) * 3)]) *
                  (2.0 * kPi / image.width) * (s1 * s1 - s0 * s0) / 2.0;
  }
  expected *= double(rho) / kPi;
  reference::ReferenceParams params;
  params.width = params.height = kSize;
  params.spp = 256;
  const reference::Film film = reference::render(scene, camera, params);
  const std::vector<vec3> half0 = film.half_average(0), half1 = film.half_average(1);
  const std::vector<vec3> image_out = film.average();
  double sum = 0.0, variance = 0.0;
  for (size_t i = 0; i < image_out.size(); ++i) {  // every pixel sees the floor (view 0.9 m)
    sum += reference::grey(image_out[i]) / expected;
    const double d = (reference::grey(half0[i]) - reference::grey(half1[i])) / expected;
    variance += d * d / 4.0;
  }
  const double n = double(image_out.size());
  const double mean = sum / n - 1.0, pixel_se = std::sqrt(variance / n);
  // The floor's mean within 4 of its standard errors (per-pixel error over sqrt(pixels)).
  EXPECT_LT(std::abs(mean), 4.0 * pixel_se / std::sqrt(n));
  EXPECT_LT(4.0 * pixel_se / std::sqrt(n), 0.01);  // and that bound would see a 1% bias
  std::printf(
      "[reference] equirect sky: floor mean %+.4f%% (expected %.5f W/(sr m^2), per-pixel "
      "standard error %.3f%%, bound %.3f%%)\n",
      100.0 * mean, expected, 100.0 * pixel_se, 400.0 * pixel_se / std::sqrt(n));
}

// HQ mode: camera rays and mirror paths that leave the scene see the sky (a mirror of
// reflectance 0.8 facing up under a constant sky, seen from above: 0.8 L on it, L past it).
TEST(HqSky, EscapingViewingPathsSeeTheSky) {
  const float sky = 2.0f, mirror_reflectance = 0.8f;
  Camera camera;
  Scene scene = test::make_lamp_floor(0.5f, 1.0f, 3.0f, 1.5f, camera);
  scene.materials[0].kind = MaterialKind::mirror;
  scene.materials[0].reflectance = vec3(mirror_reflectance);
  scene.sky = Sky{vec3(sky), -1};
  const std::vector<double> image = render_grey(Renderer::hq, scene, camera);
  int mirror = 0, past = 0;
  for (const double v : image) {
    EXPECT_GE(v, mirror_reflectance * sky * (1.0 - 1e-6));
    EXPECT_LE(v, sky * (1.0 + 1e-6));
    mirror += std::abs(v / (mirror_reflectance * sky) - 1.0) < 1e-6 ? 1 : 0;
    past += std::abs(v / sky - 1.0) < 1e-6 ? 1 : 0;
  }
  EXPECT_GT(mirror, 400);
  EXPECT_GT(past, 200);
}

// HQ mode's diffuse surfaces take the sky as soft light: from the bake's vertex radiosity
// (here an unbaked scene: 0, the direct term has no sky), or, with a final gather, from gather
// rays that leave the scene straight from the hit, which see L: a floor with nothing above it
// is then rho L exactly (every gather ray escapes).
TEST(HqSky, TheSkyIsSoftLightAndTheFinalGatherSeesIt) {
  const float rho = 0.5f, sky = 2.0f;
  Camera camera;
  Scene scene = test::make_lamp_floor(rho, 2.0f, 3.0f, 1.5f, camera);
  scene.sky = Sky{vec3(sky), -1};
  const BakedScene baked = test::unbaked(scene);
  HqParams params;
  params.width = params.height = 16;
  params.samples_per_side = 2;
  for (const int gather : {0, 1}) {
    params.final_gather = gather;
    const HqRenderer hq(baked, params);
    HqStats stats;
    const std::vector<vec3> image = hq.render(camera, 1, stats);
    const double expected = gather ? double(rho) * sky : 0.0;
    for (const vec3& v : image) EXPECT_NEAR(reference::grey(v), expected, 1e-5) << gather;
  }
}

// ---- A lamp's caustic and its bounce light ------------------------------------------------
// A point lamp of I W/sr inside a clear glass ball (smooth, no absorption) at the centre of a
// closed sphere (flat-shaded, albedo rho, mesh area A): every path from the lamp starts with a
// specular vertex, so the whole image is light tracing's (an eye path's shadow ray to the lamp
// always meets the glass). The lamp's power 4 pi I is all absorbed by the walls, and in a
// sphere every bounce lands uniformly, so the walls' radiance is rho 4 pi I / (pi A (1 - rho)):
// only (1 - rho) of it, were light paths to stop at their first diffuse vertex.
TEST(ReferenceLampCaustic, LampInAGlassBallLightsAClosedSphereToTheFurnaceValue) {
  const float rho = 0.5f, intensity = 1.0f;
  Scene scene;
  Material wall;
  wall.reflectance = vec3(rho);
  const int wall_material = test::add_material(scene, wall);
  Material glass;
  glass.kind = MaterialKind::glass;
  glass.reflectance = vec3(1.0f);
  const int glass_material = test::add_material(scene, glass);
  Mesh sphere = test::make_sphere({0, 0, 0}, 1.0f, 24, 48, wall_material, true, "walls");
  sphere.normals.clear();  // flat: see ReferenceFurnace
  double area = 0.0;
  for (uint32_t t = 0; t < sphere.triangles.size(); ++t) area += double(triangle_area(sphere, t));
  scene.meshes.push_back(sphere);
  scene.meshes.push_back(test::make_sphere({0, 0, 0}, 0.1f, 16, 32, glass_material, false, "ball"));
  scene.lights.push_back(test::point_lamp({0.0f, 0.0f, 0.0f}, intensity));
  Camera camera;
  camera.position = vec3(0.3f, 0.0f, 0.0f);
  camera.target = vec3(1.0f, 0.2f, 0.3f);
  camera.vertical_fov_deg = 60.0f;
  reference::ReferenceParams params;
  params.width = params.height = 12;
  params.spp = 128;
  params.light_paths_per_pixel = 64.0;
  const reference::Film film = reference::render(scene, camera, params);
  const std::vector<vec3> image = film.average();
  const double expected = rho * 4.0 * kPi * intensity / (kPi * area * (1.0 - rho));
  double mean = 0.0, worst = 0.0;
  for (const vec3& v : image) {
    mean += reference::grey(v) / expected;
    worst = std::max(worst, std::abs(reference::grey(v) / expected - 1.0));
  }
  mean /= double(image.size());
  const double sigma = film.noise().pixel_relative_standard_error;
  EXPECT_NEAR(mean, 1.0, 0.01);
  EXPECT_LT(worst, 5.0 * sigma + 0.01);  // the facets break the uniformity by < 1%
  std::printf(
      "[reference] lamp in glass ball: mean %+.3f%%, worst pixel %.2f%%, pixel "
      "standard error %.2f%%\n",
      100.0 * (mean - 1.0), 100.0 * worst, 100.0 * sigma);
}

// ---- Determinism ---------------------------------------------------------------------------
// Every kind at once (point, spot, directional, sky) and a mirror, so light tracing runs from
// the lamps: the same bits at 1 and 2 threads, in the reference and in HQ mode.
TEST(LampDeterminism, OneAndTwoThreadsGiveTheSameBits) {
  Camera camera;
  Scene scene = test::make_lamp_floor(0.5f, 2.0f, 3.0f, 1.5f, camera);
  Material mirror;
  mirror.kind = MaterialKind::mirror;
  mirror.reflectance = vec3(0.9f);
  const int shiny = test::add_material(scene, mirror);
  // A 1 m mirror facing down at 1.5 m over the point lamp: its caustic lands on the floor.
  scene.meshes.push_back(
      test::make_quad({-0.5f, 1.5f, -0.5f}, {1, 0, 0}, {0, 0, 1}, shiny, "mirror"));
  scene.lights.push_back(test::point_lamp({-0.2f, 1.0f, 0.1f}, 2.0f));
  scene.lights.push_back(test::spot_lamp({0.5f, 1.5f, 0.5f}, 3.0f, 0.2f, 0.4f));
  scene.lights.push_back(test::directional_lamp({0.3f, -1.0f, 0.2f}, 1.0f));
  scene.sky = Sky{vec3(0.3f), -1};
  auto limited = [](int threads, auto render) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
    return render();
  };
  reference::ReferenceParams params;
  params.width = params.height = 24;
  params.spp = 4;
  params.light_paths_per_pixel = 4.0;
  params.light_block_size = 256;
  const Accel accel(scene);
  const reference::ReferenceRenderer renderer(scene, accel, camera, params);
  reference::ReferenceStats stats;
  auto reference_image = [&] { return renderer.render(stats).average(); };
  const std::vector<vec3> one = limited(1, reference_image), two = limited(2, reference_image);
  EXPECT_GT(stats.rays.connection, 0u);  // lamp light reached the lens through the mirror
  ASSERT_EQ(one.size(), two.size());
  EXPECT_EQ(std::memcmp(one.data(), two.data(), one.size() * sizeof(vec3)), 0);
  double sum = 0.0;
  for (const vec3& v : one) sum += reference::grey(v);
  EXPECT_GT(sum, 0.0);

  const BakedScene baked = test::unbaked(scene);
  HqParams hq_params;
  hq_params.width = hq_params.height = 24;
  hq_params.samples_per_side = 2;
  hq_params.tile_size = 8;
  const HqRenderer hq(baked, hq_params);
  auto hq_image = [&] {
    HqStats stats;
    return hq.render(camera, 2, stats);
  };
  const std::vector<vec3> hq_one = limited(1, hq_image), hq_two = limited(2, hq_image);
  EXPECT_EQ(std::memcmp(hq_one.data(), hq_two.data(), hq_one.size() * sizeof(vec3)), 0);
}

INSTANTIATE_TEST_SUITE_P(Renderers, Lamps, testing::Values(Renderer::hq, Renderer::reference),
                         [](const testing::TestParamInfo<Renderer>& info) {
                           return name_of(info.param);
                         });

}  // namespace
}  // namespace lb
