// Pass 2 with lamps and a sky (issue 14): energy per light kind, lamps' direct light left to
// the viewer, a point lamp against an isotropic area light of the same power, the sky's first
// bounce against closed forms, and the same bits at 1 and 2 threads.

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "bake/accel.h"
#include "bake/light_sources.h"
#include "bake/radiosity/radiosity.h"
#include "scenes.h"
#include "test_helpers.h"

namespace lb {
namespace {

constexpr double pi = std::numbers::pi;

using test::integrate;

Lamp point_lamp(vec3 position, vec3 intensity) {
  Lamp lamp;
  lamp.kind = LampKind::point;
  lamp.position = position;
  lamp.intensity = intensity;
  return lamp;
}

Scene with_light(Scene scene, const char* kind) {
  const std::string k = kind;
  if (k == "point") {
    scene.lights.push_back(point_lamp({0.2f, 1.5f, -0.3f}, vec3(2.0f, 1.5f, 1.0f)));
  } else if (k == "spot" || k == "spot_range") {
    Lamp spot = point_lamp({-0.5f, 1.8f, 0.5f}, vec3(3.0f, 2.0f, 1.0f));
    spot.kind = LampKind::spot;
    spot.direction = glm::normalize(vec3(0.3f, -1.0f, -0.2f));
    spot.inner_cone = 0.3f;
    spot.outer_cone = 0.6f;
    if (k == "spot_range") spot.range = 1.9f;  // the window fades the floor's light
    scene.lights.push_back(spot);
  } else if (k == "directional") {
    Lamp sun;
    sun.kind = LampKind::directional;
    sun.direction = glm::normalize(vec3(0.4f, -1.0f, 0.3f));
    sun.intensity = vec3(4.0f, 3.0f, 2.0f);
    scene.lights.push_back(sun);
  } else if (k == "sky") {
    scene.sky = Sky{vec3(0.5f, 0.6f, 0.8f), -1};
  } else if (k == "sky_image") {
    test::add_sky_image(scene);
  }
  return scene;
}

// ---- energy per light kind -------------------------------------------------------------------
class LightKindEnergy : public testing::TestWithParam<const char*> {};

TEST_P(LightKindEnergy, EmittedIsAbsorbedPlusEscaped) {
  const Scene scene = with_light(test::make_open_scene(false), GetParam());
  const LightSources lights(scene);
  ASSERT_EQ(lights.size(), 1u);
  const Accel accel(scene);
  RadiosityParams params;
  params.ray_budget = 300'000;
  params.convergence = 1e-8;
  const VertexRadiosity result = solve_radiosity(scene, accel, params);
  const RadiosityStats& s = result.stats;
  ASSERT_TRUE(s.converged);
  std::printf(
      "%s: emitted %.6g W (light %.6g), absorbed %.6g, escaped %.6g, received %.6g "
      "(red)\n",
      GetParam(), double(s.power_emitted.x), double(lights.power(0).x), double(s.power_absorbed.x),
      double(s.power_escaped.x), double(s.power_received.x));
  for (int c = 0; c < 3; ++c) {
    const double emitted = s.power_emitted[c];
    // What LightSources says the light sends (lights at infinity: through the bounding disk);
    // a spot's rays carry its falloff, a sky image's rays radiance / pdf whose colour varies,
    // so their sum is a stratified estimate (measured 3e-6 for the spot, 1.5e-6 for the image).
    EXPECT_NEAR(emitted, lights.power(0)[c],
                (std::string(GetParam()) == "sky_image" ? 1e-3 : 1e-4) * emitted);
    EXPECT_GT(emitted, 0.0);
    // Sent = absorbed (surfaces, range window) + escaped + unsent; the residual is < 1e-8.
    EXPECT_NEAR(double(s.power_absorbed[c]) + s.power_escaped[c] + s.residual_unsent[c], emitted,
                1e-6 * emitted);
    EXPECT_NEAR(double(s.power_absorbed[c]) + s.power_escaped[c], emitted, 1e-6 * emitted);
    EXPECT_GT(s.power_received[c], 0.0);  // soft light reached the diffuse surfaces
  }
}

INSTANTIATE_TEST_SUITE_P(Kinds, LightKindEnergy,
                         testing::Values("point", "spot", "spot_range", "directional", "sky",
                                         "sky_image"));

// ---- lamps: direct light is the viewer's ----------------------------------------------------
// A floor alone under a lamp (or the sun): everything it gets is direct light, which the
// viewer and HQ compute at view time, so the stored soft light is exactly 0.
TEST(RadiosityLamps, DirectLampLightIsNotStored) {
  for (const char* kind : {"point", "spot", "directional"}) {
    Scene scene;
    Material white;
    white.reflectance = vec3(0.8f);
    const int w = test::add_material(scene, white);
    scene.meshes.push_back(test::make_quad({-2, 0, -2}, {0, 0, 4}, {4, 0, 0}, w, "floor"));
    scene = with_light(scene, kind);
    const Accel accel(scene);
    RadiosityParams params;
    params.ray_budget = 50'000;
    const VertexRadiosity result = solve_radiosity(scene, accel, params);
    EXPECT_GT(result.stats.light_rays, 0u) << kind;
    EXPECT_GT(result.stats.power_absorbed.x, 0.0f) << kind;  // (1 - rho) of what it received
    EXPECT_EQ(result.stats.power_received, vec3(0.0f)) << kind;
    for (const vec3& v : result.meshes[0].vertex_radiance) ASSERT_EQ(v, vec3(0.0f)) << kind;
  }
}

// A point lamp of intensity I against a small closed sphere of radiance L = I / (pi r^2): seen
// from anywhere, the sphere's intensity is pi r^2 L = I in every direction, so both send the
// same light into the room; the soft light on the floor (lamp -> wall -> floor, and on) must
// agree. The sphere (r = 2 cm, black) hides 1e-4 of the wall's view: negligible.
double soft_on_floor(bool sphere) {
  Scene scene;
  Material white;
  white.reflectance = vec3(0.8f);
  Material black;
  black.reflectance = vec3(0.0f);
  const int w = test::add_material(scene, white), b = test::add_material(scene, black);
  scene.meshes.push_back(test::make_quad({-1, 0, -1}, {0, 0, 2}, {2, 0, 0}, b, "floor"));
  scene.meshes.back().bake.patch_size = 10.0f;
  scene.meshes.push_back(test::make_quad({-1, 0, -1}, {2, 0, 0}, {0, 2, 0}, w, "wall"));
  const vec3 position(0.0f, 0.5f, -0.5f);
  const float intensity = 1.0f, radius = 0.02f;
  if (sphere) {
    Material emitter;
    emitter.reflectance = vec3(0.0f);
    emitter.emission = vec3(intensity / (float(pi) * radius * radius));
    scene.meshes.push_back(
        test::make_sphere(position, radius, 24, 48, test::add_material(scene, emitter), false));
  } else {
    scene.lights.push_back(point_lamp(position, vec3(intensity)));
  }
  const Accel accel(scene);
  RadiosityParams params;
  params.ray_budget = 4'000'000;
  params.patch_size = 0.25f;
  const VertexRadiosity result = solve_radiosity(scene, accel, params);
  return pi * integrate(result.meshes[0]).x;  // W incident on the (black) floor
}

TEST(RadiosityLamps, PointLampMatchesAnIsotropicSphereLight) {
  const double lamp = soft_on_floor(false), sphere = soft_on_floor(true);
  std::printf("floor soft light: point lamp %.6g W, sphere light %.6g W, ratio %.5f\n", lamp,
              sphere, lamp / sphere);
  ASSERT_GT(sphere, 0.0);
  // Noise of each run ~0.3% (4e6 rays); the tessellated sphere's intensity differs from a
  // true sphere's by < 0.5% (its projected area); tolerance 2%.
  EXPECT_NEAR(lamp / sphere, 1.0, 0.02);
}

// ---- the sky's first bounce is soft light ----------------------------------------------------
// A constant sky L over a floor with nothing else: the floor's irradiance is pi L, stored as
// E / pi = L (the viewer multiplies by rho: rho L); its reflected light escapes.
// A 2 x 2 m floor of `material` (and `scene`'s textures) alone under a constant sky, solved
// with 2 M rays on 0.5 m patches: its radiosity mesh.
MeshRadiosity floor_under_sky(Scene scene, const Material& material, vec3 sky) {
  const int m = test::add_material(scene, material);
  scene.meshes.push_back(test::make_quad({-1, 0, -1}, {0, 0, 2}, {2, 0, 0}, m, "floor"));
  scene.sky = Sky{sky, -1};
  const Accel accel(scene);
  RadiosityParams params;
  params.ray_budget = 2'000'000;
  params.patch_size = 0.5f;
  return solve_radiosity(scene, accel, params).meshes[0];
}

TEST(RadiositySky, ConstantSkyOverAnOpenFloorGivesL) {
  Material white;
  const float rho = 0.6f;
  white.reflectance = vec3(rho);
  const vec3 sky(0.5f, 1.0f, 2.0f);
  const MeshRadiosity floor = floor_under_sky(Scene{}, white, sky);
  const glm::dvec3 mean = integrate(floor) / double(mesh_area(floor.mesh));
  double worst = 0.0;
  for (const vec3& v : floor.vertex_radiance)
    for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(double(v[c]) / sky[c] - 1.0));
  std::printf(
      "sky L = (%g %g %g): floor mean (%.5f %.5f %.5f), worst vertex %.2f%% off; "
      "rho * mean = %.5f (rho L = %.5f)\n",
      double(sky.x), double(sky.y), double(sky.z), mean.x, mean.y, mean.z, 100.0 * worst,
      rho * mean.x, double(rho * sky.x));
  // ~1.4e5 rays per patch (16 patches): noise ~0.3% per patch, the mean ~0.1%.
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(mean[c] / sky[c], 1.0, 0.01) << c;
  EXPECT_LT(worst, 0.03);
}

// The same floor with a constant tangent-space normal map tilting its normal by alpha =
// atan(1/2): the bumped surface sees the sky through the cosine to its bumped normal over its
// own hemisphere (as HQ's direct light, the final gather and the reference do), so it receives
// (1 + cos alpha) / 2 = 0.9472 of the flat floor's pi L (a tilted plane's sky view factor).
TEST(RadiositySky, BumpedFloorReceivesItsSkyViewFactor) {
  Scene scene;
  Texture tilt;  // tangent-space (0.5, 0, 1), glTF encoding c = (n + 1) / 2
  tilt.width = tilt.height = 1;
  tilt.channels = 3;
  tilt.texels = {0.75f, 0.5f, 1.0f};
  scene.textures.push_back(tilt);
  Material bumped;
  bumped.reflectance = vec3(0.6f);
  bumped.bump = BumpKind::normal_map;
  bumped.bump_texture = 0;
  const float sky = 1.0f;
  const MeshRadiosity floor = floor_under_sky(scene, bumped, vec3(sky));
  const double mean = integrate(floor).x / double(mesh_area(floor.mesh));
  const double expected = sky * (1.0 + 2.0 / std::sqrt(5.0)) / 2.0;
  std::printf("bumped floor under a constant sky: mean E/pi %.5f, expected %.5f (flat %.1f)\n",
              mean, expected, double(sky));
  // Noise as the flat floor's (~0.1% on the mean); 1% tolerance, 5% below the flat value.
  EXPECT_NEAR(mean / expected, 1.0, 0.01);
}

// Howell's catalogue C-11: form factor between two directly opposed parallel rectangles
// a x b at distance c.
double parallel_rectangles(double a, double b, double c) {
  const double x = a / c, y = b / c;
  const double x1 = std::sqrt(1.0 + x * x), y1 = std::sqrt(1.0 + y * y);
  return 2.0 / (pi * x * y) *
         (std::log(x1 * y1 / std::sqrt(1.0 + x * x + y * y)) + x * y1 * std::atan(x / y1) +
          y * x1 * std::atan(y / x1) - x * std::atan(x) - y * std::atan(y));
}

// An open box (floor a x a, black walls of height h, no lid) under a constant sky L: the floor
// sees the sky only through the opening, so its incident power is pi L a^2 F(opening -> floor)
// (reciprocity), i.e. an integral of the stored E/pi of L a^2 F; at the centre the stored
// value is L times the point-to-opening form factor, from Lambert's polygon formula.
TEST(RadiositySky, OpenBoxFloorMatchesTheFormFactor) {
  EXPECT_NEAR(parallel_rectangles(1.0, 1.0, 1.0), 0.19982, 1e-4);  // the table's value
  Scene scene;
  Material floor_material, black;
  floor_material.reflectance = vec3(0.5f);
  black.reflectance = vec3(0.0f);
  const int f = test::add_material(scene, floor_material), b = test::add_material(scene, black);
  const float a = 2.0f, h = 1.0f;
  const vec3 x(a, 0, 0), y(0, h, 0), z(0, 0, a);
  scene.meshes.push_back(test::make_quad({0, 0, 0}, z, x, f, "floor"));  // faces +y
  scene.meshes.push_back(test::make_quad({0, 0, 0}, x, y, b, "wall -z"));
  scene.meshes.push_back(test::make_quad({0, 0, a}, y, x, b, "wall +z"));
  scene.meshes.push_back(test::make_quad({0, 0, 0}, y, z, b, "wall -x"));
  scene.meshes.push_back(test::make_quad({a, 0, 0}, z, y, b, "wall +x"));
  const float sky = 1.5f;
  scene.sky = Sky{vec3(sky), -1};
  const Accel accel(scene);
  RadiosityParams params;
  params.ray_budget = 4'000'000;
  params.patch_size = 0.25f;
  const VertexRadiosity result = solve_radiosity(scene, accel, params);
  const double expected_integral = double(sky) * a * a * parallel_rectangles(a, a, h);
  const double integral = integrate(result.meshes[0]).x;
  // Centre: the vertex nearest (a/2, 0, a/2) of the refined floor (a patch corner).
  const MeshRadiosity& floor = result.meshes[0];
  size_t centre = 0;
  for (size_t v = 0; v < floor.mesh.positions.size(); ++v)
    if (glm::length(floor.mesh.positions[v] - vec3(a / 2, 0, a / 2)) <
        glm::length(floor.mesh.positions[centre] - vec3(a / 2, 0, a / 2)))
      centre = v;
  const vec3 c = floor.mesh.positions[centre];
  const double expected_centre =
      test::polygon_irradiance({{0, h, 0}, {a, h, 0}, {a, h, a}, {0, h, a}}, glm::dvec3(c),
                               {0, 1, 0}, sky) /
      pi;
  const double at_centre = floor.vertex_radiance[centre].x;
  std::printf(
      "open box: floor integral %.6g W/sr (form factor %.6g), centre %.5f (Lambert "
      "%.5f)\n",
      integral, expected_integral, at_centre, expected_centre);
  // ~8e5 rays on the floor: the integral's noise ~0.1%; tolerance 1%.
  EXPECT_NEAR(integral / expected_integral, 1.0, 0.01);
  // One vertex: the mean of the four patches (0.25 m) around it, whose curvature bias at the
  // centre is < 0.5%; noise ~1.5% per patch, ~0.8% for four; tolerance 3%.
  EXPECT_NEAR(at_centre / expected_centre, 1.0, 0.03);
}

// ---- determinism -----------------------------------------------------------------------------
TEST(RadiosityLamps, SameBitsWithOneAndTwoThreads) {
  Scene scene = with_light(with_light(test::make_open_scene(false), "point"), "spot_range");
  scene = with_light(with_light(scene, "directional"), "sky");
  const Accel accel(scene);
  RadiosityParams params;
  params.ray_budget = 200'000;
  auto solve = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
    return solve_radiosity(scene, accel, params);
  };
  const VertexRadiosity one = solve(1), two = solve(2);
  ASSERT_EQ(one.meshes.size(), two.meshes.size());
  for (size_t m = 0; m < one.meshes.size(); ++m)
    EXPECT_TRUE(test::same_bits(one.meshes[m].vertex_radiance, two.meshes[m].vertex_radiance))
        << "mesh " << m;
  EXPECT_GT(one.stats.power_received.x, 0.0f);
  EXPECT_EQ(one.stats.light_rays, two.stats.light_rays);
  params.seed = 2;  // another seed gives other noise: the comparison above can fail
  const VertexRadiosity other = solve(2);
  EXPECT_FALSE(test::same_bits(one.meshes[0].vertex_radiance, other.meshes[0].vertex_radiance));
}

// ---- a double-sided emitter -------------------------------------------------------------------
// glTF doubleSided emission: the panel shoots twice one face's power, half of it upwards, so
// the emitted power is 2 pi L A, it balances, and the floor above gets what the floor below
// gets (by symmetry). Before: pi L A, and the ceiling floor held 2-3x the floor's light.
TEST(RadiosityLights, DoubleSidedEmitterShootsFromBothFaces) {
  const float size = 0.5f, radiance = 4.0f;
  const test::TwoSidedPanel panel = test::make_two_sided_panel(size, radiance, 0.5f, 0.5f);
  const Accel accel(panel.scene);
  RadiosityParams params;
  params.ray_budget = 1'000'000;
  params.patch_size = 0.25f;
  const VertexRadiosity result = solve_radiosity(panel.scene, accel, params);
  const RadiosityStats& s = result.stats;
  const double emitted = 2.0 * pi * radiance * size * size;
  EXPECT_NEAR(s.power_emitted.x, emitted, 1e-4 * emitted);
  const double accounted = double(s.power_absorbed.x) + s.power_escaped.x + s.residual_unsent.x;
  EXPECT_NEAR(accounted / s.power_emitted.x, 1.0, 1e-3);
  const double below = integrate(result.meshes[1]).x, above = integrate(result.meshes[2]).x;
  std::printf("double-sided panel: emitted %.5g W (2 pi L A %.5g), floor %.5g, ceiling %.5g\n",
              double(s.power_emitted.x), emitted, below, above);
  EXPECT_NEAR(above / below, 1.0, 0.03);
}

}  // namespace
}  // namespace lb
