// The reference renderer against closed forms: a furnace (a closed emitting and reflecting
// sphere), a polygon light's direct light (Lambert's formula), a planar mirror's caustic (the
// mirrored light's polygon irradiance, the light-tracing half alone), and the partition
// (light tracing on or off estimates the same image).

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "bake/reference/reference.h"
#include "bake/sampling.h"
#include "bake/thin_lens_camera.h"
#include "reference_test_support.h"
#include "scenes.h"
#include "test_helpers.h"

namespace lb {
namespace {

using namespace reference;

constexpr double kPi = std::numbers::pi;

Material diffuse(float reflectance, float emission = 0.0f) {
  Material m;
  m.reflectance = vec3(reflectance);
  m.emission = vec3(emission);
  return m;
}

// The mean over pixel (x, y) of closed_form(point of the plane y = plane_y seen through a
// pinhole), on a 4 x 4 grid of the pixel's area: a closed form read at the pixel centre alone
// is off by its curvature over the footprint (0.2% here). nullopt if any point fails `keep`.
template <class ClosedForm, class Keep>
std::optional<double> pixel_mean(const Camera& camera, const ReferenceParams& p, int x, int y,
                                 double plane_y, ClosedForm closed_form, Keep keep) {
  const ThinLensCamera lens(camera, p.width, p.height);
  constexpr int n = 4;
  double sum = 0.0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const vec2 film(float(x) + (float(i) + 0.5f) / n, float(y) + (float(j) + 0.5f) / n);
      const Ray ray = lens.generate(film, {0.5f, 0.5f});
      const double t = (plane_y - double(ray.origin.y)) / double(ray.direction.y);
      const glm::dvec3 point = glm::dvec3(ray.origin) + t * glm::dvec3(ray.direction);
      if (!(t > 0.0) || !keep(point)) return std::nullopt;
      sum += closed_form(point);
    }
  return sum / (n * n);
}

// Pixel values (grey) against a closed form on the plane y = plane_y, over the pixels whose
// whole footprint passes `keep`: the worst and RMS relative error and the ratio of the sums.
struct Comparison {
  double worst = 0.0, rms = 0.0, sum_ratio = 0.0;
  int pixels = 0;
};
template <class ClosedForm, class Keep>
Comparison compare_on_plane(const std::vector<double>& values, const Camera& camera,
                            const ReferenceParams& params, double plane_y, ClosedForm closed_form,
                            Keep keep) {
  Comparison c;
  double sum = 0.0, expected_sum = 0.0, squares = 0.0;
  for (int y = 0; y < params.height; ++y)
    for (int x = 0; x < params.width; ++x) {
      const std::optional<double> expected =
          pixel_mean(camera, params, x, y, plane_y, closed_form, keep);
      if (!expected) continue;
      const double value = values[size_t(y * params.width + x)];
      const double error = value / *expected - 1.0;
      c.worst = std::max(c.worst, std::abs(error));
      squares += error * error;
      sum += value;
      expected_sum += *expected;
      ++c.pixels;
    }
  c.rms = c.pixels ? std::sqrt(squares / c.pixels) : 0.0;
  c.sum_ratio = expected_sum > 0.0 ? sum / expected_sum : 0.0;
  return c;
}

// ---- The camera's inverse ----------------------------------------------------------------
// ThinLensCamera::connect undoes generate: a point on the ray generate() makes for a film
// point and lens sample connects back to that film point and lens point, pinhole or lens.
TEST(ReferenceCamera, ConnectInvertsGenerate) {
  Camera camera;
  camera.position = vec3(0.3f, 1.2f, 2.0f);
  camera.target = vec3(-0.2f, 0.4f, -1.0f);
  camera.vertical_fov_deg = 55.0f;
  for (const float aperture : {0.0f, 0.05f}) {
    camera.aperture_radius = aperture;
    const ThinLensCamera lens(camera, 64, 48);
    Rng rng(7);
    for (int k = 0; k < 100; ++k) {
      const vec2 film(64.0f * rng.next_float(), 48.0f * rng.next_float());
      const vec2 u = rng.next_2d();
      const Ray ray = lens.generate(film, u);
      const vec3 point = ray.origin + (0.5f + 4.0f * rng.next_float()) * ray.direction;
      ThinLensCamera::Connection c;
      ASSERT_TRUE(lens.connect(point, u, c));
      EXPECT_NEAR(c.film.x, film.x, 2e-3f);
      EXPECT_NEAR(c.film.y, film.y, 2e-3f);
      EXPECT_LT(glm::length(c.lens_point - ray.origin), 1e-5f);
      EXPECT_GT(c.importance, 0.0f);
    }
    ThinLensCamera::Connection c;
    EXPECT_FALSE(
        lens.connect(camera.position - (camera.target - camera.position), {0.5f, 0.5f}, c));
  }
}

// ---- Furnace ------------------------------------------------------------------------------
// A closed sphere whose whole inside emits L_e and reflects with albedo rho: the radiance
// everywhere inside is L_e / (1 - rho), for any closed tessellation (the constant solves the
// rendering equation because every direction from the surface meets the surface). Every path
// length counts: this checks next-event estimation and the hit on an emitter (MIS weights
// summing to one), the emitter's own reflection, and Russian roulette.
TEST(ReferenceFurnace, ClosedEmittingSphereIsLeOverOneMinusRho) {
  for (const float rho : {0.5f, 0.8f}) {
    Scene scene;
    const int wall = test::add_material(scene, diffuse(rho, 1.0f));
    Mesh sphere = test::make_sphere({0, 0, 0}, 1.0f, 24, 48, wall, true, "sphere");
    // Flat shading: with interpolated normals the Lambertian BRDF (zero below the geometric
    // plane) reflects less than rho, and the closed form would not hold.
    sphere.normals.clear();
    scene.meshes.push_back(sphere);
    Camera camera;
    camera.position = vec3(0.1f, -0.2f, 0.05f);
    camera.target = vec3(1.0f, 0.3f, -0.4f);
    camera.vertical_fov_deg = 90.0f;
    ReferenceParams params;
    params.width = params.height = 24;
    params.spp = rho > 0.7f ? 512 : 256;
    const Film film = render(scene, camera, params);
    const double expected = 1.0 / (1.0 - double(rho));
    const std::vector<vec3> image = film.average();
    double worst = 0.0, mean = 0.0;
    for (const vec3& v : image) {
      worst = std::max(worst, std::abs(grey(v) / expected - 1.0));
      mean += grey(v) / expected;
    }
    mean /= double(image.size());
    const double sigma = film.noise().pixel_relative_standard_error;
    // Measured (24 x 24 pixels, 256 / 512 spp): worst pixel 0.71% off (rho 0.5) and 0.63%
    // (rho 0.8), image mean within 0.01%, per-pixel standard error from the halves 0.21% and
    // 0.20%: 1% is about five standard errors.
    EXPECT_LT(worst, 0.01) << "rho " << rho << " sigma " << sigma;
    EXPECT_LT(4.0 * sigma, 0.01) << "rho " << rho;
    EXPECT_NEAR(mean, 1.0, 0.002) << "rho " << rho;
    RecordProperty("sphere_rho" + std::to_string(int(rho * 10)),
                   "worst " + std::to_string(worst) + " mean " + std::to_string(mean) + " sigma " +
                       std::to_string(sigma));
  }
}

// A closed sphere (flat-shaded, albedo rho) whose top cap emits L_e, seen from its centre
// looking down at the wall: every point of a sphere sees every area element with form factor
// dA / A, so the cap's power P = pi L_e A_cap lands uniformly and the wall's radiance is
// rho P / ((1 - rho) pi A) everywhere (the radiosity tests' ClosedSphere; A and A_cap are
// the mesh's). The facets of a 48 x 96 sphere break the uniformity slightly. Measured (12 x 12,
// 1024 spp): worst pixel 0.53% off, mean within 0.01%, per-pixel standard error 0.15%.
TEST(ReferenceFurnace, ClosedSphereWithAnEmittingCapIsUniformAndAnalytic) {
  const float rho = 0.5f;
  Scene scene = test::make_emitting_sphere(rho, 1.0f, 25.0f, 48, 96);
  for (Mesh& mesh : scene.meshes) mesh.normals.clear();
  const double area = double(mesh_area(scene.meshes[0])) + mesh_area(scene.meshes[1]);
  const double power = kPi * mesh_area(scene.meshes[1]);
  const double expected = rho * power / ((1.0 - rho) * kPi * area);
  Camera camera;
  camera.position = vec3(0.0f);
  camera.target = vec3(0.0f, -1.0f, 0.0f);
  camera.up = vec3(0.0f, 0.0f, 1.0f);
  camera.vertical_fov_deg = 90.0f;
  ReferenceParams params;
  params.width = params.height = 12;
  params.spp = 1024;
  const Film film = render(scene, camera, params);
  double worst = 0.0, mean = 0.0;
  for (const vec3& v : film.average()) {
    worst = std::max(worst, std::abs(grey(v) / expected - 1.0));
    mean += grey(v) / expected / double(params.width * params.height);
  }
  const double sigma = film.noise().pixel_relative_standard_error;
  EXPECT_LT(worst, 0.01) << "sigma " << sigma;
  EXPECT_NEAR(mean, 1.0, 0.003);
  RecordProperty("cap", "worst " + std::to_string(worst) + " mean " + std::to_string(mean) +
                            " sigma " + std::to_string(sigma));
}

// ---- Direct light from a polygon ----------------------------------------------------------
// A 2 x 2 m floor (albedo 0.5) under a 0.5 x 0.5 m light facing down at 1 m (black, so no
// light bounces back): the floor's radiance is rho E / pi with E from Lambert's formula.
TEST(ReferenceDirect, FloorUnderASquareLightMatchesLambertsFormula) {
  const float rho = 0.5f, radiance = 10.0f, h = 0.25f, height = 1.0f;
  Scene scene;
  const int floor_material = test::add_material(scene, diffuse(rho));
  const int light_material = test::add_material(scene, diffuse(0.0f, radiance));
  scene.meshes.push_back(
      test::make_quad({-1, 0, 1}, {2, 0, 0}, {0, 0, -2}, floor_material, "floor"));
  scene.meshes.push_back(
      test::make_quad({-h, height, -h}, {2 * h, 0, 0}, {0, 0, 2 * h}, light_material, "light"));
  Camera camera;
  camera.position = vec3(0.0f, 0.6f, 1.6f);
  camera.target = vec3(0.0f, 0.0f, 0.0f);
  camera.vertical_fov_deg = 40.0f;
  ReferenceParams params;
  params.width = params.height = 16;
  params.spp = 2048;
  const Film film = render(scene, camera, params);
  const std::vector<vec3> image = film.average();
  const std::vector<glm::dvec3> light = {
      {-h, height, -h}, {h, height, -h}, {h, height, h}, {-h, height, h}};
  std::vector<double> values;
  for (const vec3& v : image) values.push_back(grey(v));
  const Comparison c = compare_on_plane(
      values, camera, params, 0.0,
      [&](glm::dvec3 p) {
        return rho * test::polygon_irradiance(light, p, {0, 1, 0}, radiance) / kPi;
      },
      [](glm::dvec3 p) { return std::abs(p.x) < 0.9 && std::abs(p.z) < 0.9; });  // on the floor
  ASSERT_GT(c.pixels, 100);
  const double sigma = film.noise().pixel_relative_standard_error;
  // Measured (160 floor pixels, 2048 spp): worst pixel 1.8% off, RMS 0.59%, image sum 0.09%
  // off, per-pixel standard error from the halves 0.63%: 2.5% is four standard errors.
  EXPECT_LT(c.worst, 0.025) << "sigma " << sigma;
  RecordProperty("direct", "worst " + std::to_string(c.worst) + " rms " + std::to_string(c.rms) +
                               " sum " + std::to_string(c.sum_ratio) + " sigma " +
                               std::to_string(sigma));
  EXPECT_NEAR(c.sum_ratio, 1.0, 0.003);
}

// Whether every line from ceiling point p to the light's image crosses the mirror (the plane
// y = x, |x| <= 0.5, |z| <= 0.5): the corners suffice, the mirror and the image being convex.
bool whole_image_in_mirror(glm::dvec3 p, const std::vector<glm::dvec3>& image) {
  for (const glm::dvec3& q : image) {
    const glm::dvec3 d = q - p;
    const double t = (p.x - p.y) / (d.y - d.x);  // p + t d on y = x
    const glm::dvec3 m = p + t * d;
    if (!(t > 0.0 && t < 1.0) || std::abs(m.x) > 0.5 || std::abs(m.z) > 0.5) return false;
  }
  return true;
}

// A 45 degree mirror in the plane y = x (facing (-1, 1, 0)) and a square light (half size h)
// in the plane x = -1 facing +x: the light's mirror image lies in the plane y = -1 facing up.
// A white ceiling at y = 0.9 facing down receives the direct light and, through the mirror,
// R_m times the irradiance of the image; `camera` looks up at the ceiling past the mirror.
Scene light_beside_a_diagonal_mirror(float rho, float mirror_reflectance, float radiance, float h,
                                     Camera& camera) {
  Scene scene;
  const int white = test::add_material(scene, diffuse(rho));
  const int light_material = test::add_material(scene, diffuse(0.0f, radiance));
  Material mirror;
  mirror.kind = MaterialKind::mirror;
  mirror.reflectance = vec3(mirror_reflectance);
  const int shiny = test::add_material(scene, mirror);
  scene.meshes.push_back(
      test::make_quad({-0.5f, -0.5f, -0.5f}, {0, 0, 1}, {1, 1, 0}, shiny, "mirror"));
  scene.meshes.push_back(
      test::make_quad({-1, -h, -h}, {0, 2 * h, 0}, {0, 0, 2 * h}, light_material, "light"));
  scene.meshes.push_back(
      test::make_quad({-0.6f, 0.9f, -0.6f}, {1.2f, 0, 0}, {0, 0, 1.2f}, white, "ceiling"));
  camera.position = vec3(-0.3f, 0.2f, 0.0f);
  camera.target = vec3(-0.1f, 0.9f, 0.0f);
  camera.up = vec3(0, 0, 1);
  camera.vertical_fov_deg = 50.0f;
  return scene;
}

// What light tracing adds: the grey render with `light_paths_per_pixel` light paths minus the
// same render without (same seed: the eye paths draw the same numbers).
std::vector<double> light_traced_part(const Scene& scene, const Camera& camera,
                                      ReferenceParams params, double light_paths_per_pixel) {
  params.light_paths_per_pixel = light_paths_per_pixel;
  const std::vector<vec3> a = render(scene, camera, params).average();
  params.light_paths_per_pixel = 0.0;
  const std::vector<vec3> b = render(scene, camera, params).average();
  std::vector<double> difference;
  for (size_t i = 0; i < a.size(); ++i) difference.push_back(grey(a[i]) - grey(b[i]));
  return difference;
}

// ---- A planar mirror's caustic ------------------------------------------------------------
// Light tracing counts exactly the caustic (L S D E), so the render minus the same render
// without light paths (same seed: the eye paths draw the same numbers) is R_m rho E_image / pi.
TEST(ReferenceCaustic, PlanarMirrorCausticMatchesTheMirroredLight) {
  const float rho = 0.8f, mirror_reflectance = 0.9f, radiance = 40.0f, h = 0.1f;
  Camera camera;
  const Scene scene = light_beside_a_diagonal_mirror(rho, mirror_reflectance, radiance, h, camera);
  ReferenceParams params;
  params.width = params.height = 12;
  params.spp = 256;
  const std::vector<double> caustic = light_traced_part(scene, camera, params, 256.0);
  const std::vector<glm::dvec3> image = {{-h, -1, -h}, {h, -1, -h}, {h, -1, h}, {-h, -1, h}};
  const Comparison c = compare_on_plane(
      caustic, camera, params, 0.9,
      [&](glm::dvec3 p) {
        return mirror_reflectance * rho * test::polygon_irradiance(image, p, {0, -1, 0}, radiance) /
               kPi;
      },
      [&](glm::dvec3 p) {
        return std::abs(p.x) < 0.58 && std::abs(p.z) < 0.58 && whole_image_in_mirror(p, image);
      });
  ASSERT_GT(c.pixels, 40);
  // Measured (144 pixels, 256 passes of 256 light paths per pixel): worst pixel 4.7% off, RMS
  // 1.8% (the light paths' per-pixel noise), the sum 0.20% off (its standard error about
  // 1.8% / 12 = 0.15%). 7% is about four standard errors.
  EXPECT_LT(c.worst, 0.07);
  RecordProperty("caustic", "worst " + std::to_string(c.worst) + " rms " + std::to_string(c.rms) +
                                " sum " + std::to_string(c.sum_ratio));
  EXPECT_NEAR(c.sum_ratio, 1.0, 0.005);
}

// A point lamp of I W/sr at (0.5, 0, 0) before a vertical mirror in the plane x = 0 (facing +x,
// |y|, |z| <= 0.5) under a white ceiling at y = 0.9 facing down: only light tracing can find
// the caustic (no scattered ray hits a point), and the mirror's image of the lamp at
// (-0.5, 0, 0) gives the ceiling R_m rho I cos / (pi d^2) with cos = 0.9 / d. The mirror is
// perpendicular to the ceiling, so the ceiling's own light never comes back to it through
// the mirror (the light tracer's later bounces add nothing here).
TEST(ReferenceCaustic, PointLampCausticMatchesTheMirroredLamp) {
  const float rho = 0.8f, mirror_reflectance = 0.9f, intensity = 2.0f;
  Scene scene;
  const int white = test::add_material(scene, diffuse(rho));
  Material mirror;
  mirror.kind = MaterialKind::mirror;
  mirror.reflectance = vec3(mirror_reflectance);
  const int shiny = test::add_material(scene, mirror);
  scene.meshes.push_back(
      test::make_quad({0.0f, -0.5f, -0.5f}, {0, 1, 0}, {0, 0, 1}, shiny, "mirror"));
  scene.meshes.push_back(
      test::make_quad({-0.2f, 0.9f, -0.8f}, {1.8f, 0, 0}, {0, 0, 1.6f}, white, "ceiling"));
  Lamp lamp;
  lamp.kind = LampKind::point;
  lamp.position = vec3(0.5f, 0.0f, 0.0f);
  lamp.intensity = vec3(intensity);
  scene.lights.push_back(lamp);
  Camera camera;
  camera.position = vec3(0.8f, 0.2f, 0.0f);
  camera.target = vec3(0.8f, 0.9f, 0.0f);
  camera.up = vec3(0, 0, 1);
  camera.vertical_fov_deg = 50.0f;
  ReferenceParams params;
  params.width = params.height = 12;
  params.spp = 256;
  const std::vector<double> caustic = light_traced_part(scene, camera, params, 1024.0);
  const glm::dvec3 image(-0.5, 0.0, 0.0);
  // Whether the line from ceiling point p to the image crosses the mirror.
  auto through_mirror = [&](glm::dvec3 p) {
    const double t = p.x / (p.x - image.x);  // p + t (image - p) on x = 0
    const glm::dvec3 m = p + t * (image - p);
    return t > 0.0 && t < 1.0 && std::abs(m.y) < 0.5 && std::abs(m.z) < 0.5;
  };
  const Comparison c = compare_on_plane(
      caustic, camera, params, 0.9,
      [&](glm::dvec3 p) {
        const double d = glm::length(p - image);
        return mirror_reflectance * rho * intensity * (p.y - image.y) / (kPi * d * d * d);
      },
      [&](glm::dvec3 p) { return std::abs(p.z) < 0.78 && through_mirror(p); });
  ASSERT_GT(c.pixels, 60);
  // Measured (144 pixels, 256 passes of 1024 light paths per pixel): worst pixel 5.7% off, RMS
  // 2.1% (a point lamp sends most of its paths past the mirror), the sum 0.17% off (its
  // standard error about 2.1% / 12 = 0.18%). 9% is about four per-pixel errors, 0.6% three of
  // the sum's.
  EXPECT_LT(c.worst, 0.09);
  RecordProperty("caustic", "worst " + std::to_string(c.worst) + " rms " + std::to_string(c.rms) +
                                " sum " + std::to_string(c.sum_ratio));
  std::printf("point caustic: %d pixels, worst %.2f%%, rms %.2f%%, sum %+.3f%%\n", c.pixels,
              100.0 * c.worst, 100.0 * c.rms, 100.0 * (c.sum_ratio - 1.0));
  EXPECT_NEAR(c.sum_ratio, 1.0, 0.006);
}

// ---- The partition -------------------------------------------------------------------------
// The same scene with a larger light, rendered with the caustic from light tracing and from
// the path tracer's own scattered rays: each path is counted once either way, so the images
// agree within their noise. For the mirror seen through a
// pinhole, for glossy metal (specular in this project's partition), and through a thin lens
// (light paths then sample the lens).
struct PartitionCase {
  const char* name;
  MaterialKind kind;
  float aperture_radius;  // metres
};
void PrintTo(const PartitionCase& c, std::ostream* os) {
  *os << c.name;
}
class ReferencePartition : public testing::TestWithParam<PartitionCase> {};

TEST_P(ReferencePartition, LightTracingAndPathTracingCountTheCausticOnce) {
  Camera camera;
  Scene scene = light_beside_a_diagonal_mirror(0.8f, 0.9f, 10.0f, 0.3f, camera);
  scene.materials[2].kind = GetParam().kind;
  scene.materials[2].roughness = 0.3f;
  camera.aperture_radius = GetParam().aperture_radius;
  ReferenceParams params;
  params.width = params.height = 16;
  params.spp = 2048;
  params.light_paths_per_pixel = 4.0;
  const Film split = render(scene, camera, params);
  params.light_paths_per_pixel = 0.0;
  const Film no_caustic = render(scene, camera, params);
  params.light_tracing = false;
  const Film eye_only = render(scene, camera, params);
  // The three renders share their eye paths' random numbers, so everything but the caustic
  // cancels: split - eye_only is the light tracer's caustic minus the path tracer's, pass by
  // pass, and its standard error comes from the spread of the per-pass differences.
  const size_t n = split.pass_means.size();
  double d = 0.0, d2 = 0.0, caustic = 0.0;
  for (size_t k = 0; k < n; ++k) {
    const double dk = split.pass_means[k] - eye_only.pass_means[k];
    d += dk;
    d2 += dk * dk;
    caustic += split.pass_means[k] - no_caustic.pass_means[k];
  }
  d /= double(n);
  caustic /= double(n);
  const double se = std::sqrt((d2 / double(n) - d * d) / double(n - 1));
  RecordProperty("partition", "difference " + std::to_string(d) + " se " + std::to_string(se) +
                                  " caustic " + std::to_string(caustic));
  // Measured (16 x 16, 2048 passes; W/(sr m^2)): mirror 0.00061 (0.34 se), glossy 0.00184
  // (1.01 se), lens 0.00073 (0.40 se); se 0.0018, under 1% of the caustic's 0.20-0.21.
  EXPECT_LT(std::abs(d), 4.0 * se) << "difference " << d << ", se " << se;
  // Four standard errors are under a tenth of the caustic: a caustic counted twice, or not at
  // all, or 10% off, fails.
  EXPECT_LT(4.0 * se, 0.1 * caustic) << caustic;
}

INSTANTIATE_TEST_SUITE_P(Cases, ReferencePartition,
                         testing::Values(PartitionCase{"mirror", MaterialKind::mirror, 0.0f},
                                         PartitionCase{"glossy", MaterialKind::glossy, 0.0f},
                                         PartitionCase{"lens", MaterialKind::mirror, 0.05f}),
                         [](const auto& info) { return std::string(info.param.name); });

// A double-sided emissive square (glTF doubleSided) between two floors, direct light only:
// each floor's radiance is rho E / pi with E from Lambert's formula for one face. Before: the
// floor above the panel was black.
TEST(ReferenceDirect, DoubleSidedLightLightsTheFloorsAboveAndBelow) {
  const float rho = 0.5f, radiance = 10.0f, size = 0.5f, height = 1.0f;
  const test::TwoSidedPanel panel = test::make_two_sided_panel(size, radiance, height, rho);
  ReferenceParams params;
  params.width = params.height = 12;
  params.spp = 1024;
  params.terms = Terms::direct;
  for (const float side : {-1.0f, 1.0f}) {
    Camera camera;
    camera.position = vec3(0.0f, side * 0.4f, 1.6f);
    camera.target = vec3(0.0f, side * height, 0.0f);
    camera.vertical_fov_deg = 40.0f;
    const Film film = render(panel.scene, camera, params);
    std::vector<double> values;
    for (const vec3& v : film.average()) values.push_back(grey(v));
    const Comparison c = compare_on_plane(
        values, camera, params, side * height,
        [&](glm::dvec3 p) {
          return rho * test::polygon_irradiance(panel.corners, p, {0, -side, 0}, radiance) / kPi;
        },
        [](glm::dvec3 p) { return std::abs(p.x) < 0.9 && std::abs(p.z) < 0.9; });
    ASSERT_GT(c.pixels, 40) << "side " << side;
    // 1024 spp: per-pixel standard error about 1%.
    EXPECT_LT(c.worst, 0.05) << "side " << side;
    EXPECT_NEAR(c.sum_ratio, 1.0, 0.01) << "side " << side;
  }
}

}  // namespace
}  // namespace lb
