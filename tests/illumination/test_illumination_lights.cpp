// Pass 1 with lamps and a sky (issue 14): caustics of a point lamp, a spot and the sun in a
// planar mirror against the mirrored light's closed form, the sky through a mirror against
// Lambert's polygon formula, energy per light kind, the inverse ray maps of the aimed
// feelers, and the same bits at 1 and 2 threads.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "bake/illumination/illumination.h"
#include "bake/illumination/light_rays.h"
#include "bake/light_sources.h"
#include "map_lookup.h"
#include "sun_over_mirror.h"
#include "scenes.h"
#include "test_helpers.h"

namespace lb {
namespace {

constexpr double pi = std::numbers::pi;

Material mirror_material(float reflectance) {
  Material m;
  m.kind = MaterialKind::mirror;
  m.reflectance = vec3(reflectance);
  return m;
}

// A 2 x 2 m mirror on the floor (z = 0, facing up), the lamp 0.5 m above its centre, and a
// diffuse ceiling at z = 1 facing down (texel 0.1 m) that gets the lamp's light only via the
// mirror as a caustic (its direct light is the viewer's).
struct LampOverMirror {
  Scene scene;
  float reflectance = 0.8f;
  float intensity = 2.0f;  // W/sr
  explicit LampOverMirror(Lamp lamp) {
    const int white = test::add_material(scene, Material{});
    const int shiny = test::add_material(scene, mirror_material(reflectance));
    scene.meshes.push_back(test::make_quad({-1, -1, 0}, {2, 0, 0}, {0, 2, 0}, shiny, "mirror"));
    Mesh ceiling = test::make_quad({-1, -1, 1}, {0, 2, 0}, {2, 0, 0}, white, "ceiling");
    ceiling.bake.texel_size = 0.1f;
    scene.meshes.push_back(ceiling);
    lamp.position = vec3(0, 0, 0.5f);
    lamp.intensity = vec3(intensity);
    scene.lights.push_back(lamp);
  }
  // R I cos / d^2 from the lamp's image at z = -0.5 (times the spot's falloff towards p), as
  // stored: E / pi.
  double expected(vec3 p) const {
    const vec3 image(0, 0, -0.5f);
    const vec3 to_p = p - image;
    const double d = glm::length(to_p), cos_ceiling = 1.5 / d;
    // The image of a downward spot points up: its falloff at p is the spot's at the mirrored
    // direction.
    const Lamp& lamp = scene.lights[0];
    const vec3 mirrored = glm::normalize(vec3(to_p.x, to_p.y, -to_p.z));
    const double falloff = spot_falloff(lamp, glm::dot(mirrored, lamp.direction));
    return reflectance * intensity * falloff * cos_ceiling / (d * d) / pi;
  }
};

struct MapError {
  double mean = 0.0, worst = 0.0;  // relative errors
  double map_sum = 0.0, expected_sum = 0.0;
};

// The map of mesh 1 (red channel) against `expected` at the points p = (x, y, height), x in
// [lo.x, hi.x] and y in [lo.y, hi.y] 5 cm apart, where `use` says.
template <class Expected, class Use>
MapError map_error(const IlluminationMaps& maps, const Scene& scene, vec2 lo, vec2 hi, float height,
                   Expected expected, Use use) {
  MapError e;
  int count = 0;
  for (float y = lo.y; y <= hi.y + 1e-3f; y += 0.05f)
    for (float x = lo.x; x <= hi.x + 1e-3f; x += 0.05f) {
      const vec3 p(x, y, height);
      if (!use(p)) continue;
      const double value = test::map_at(maps, scene, 1, p).x, exact = expected(p);
      const double error = std::abs(value / exact - 1);
      e.mean += error;
      e.worst = std::max(e.worst, error);
      e.map_sum += value, e.expected_sum += exact;
      ++count;
    }
  e.mean /= std::max(count, 1);
  return e;
}

// The ceiling of a LampOverMirror, 15 cm from its edge.
template <class Use>
MapError ceiling_error(const LampOverMirror& s, const IlluminationMaps& maps, Use use) {
  return map_error(
      maps, s.scene, vec2(-0.85f), vec2(0.85f), 1.0f, [&](vec3 p) { return s.expected(p); }, use);
}
bool everywhere(vec3) {
  return true;
}

Lamp lamp_of(LampKind kind) {
  Lamp lamp;
  lamp.kind = kind;
  lamp.direction = vec3(0, 0, -1);
  lamp.inner_cone = 0.4f;  // on the ceiling: r < 1.5 tan 0.4 = 0.63 m
  lamp.outer_cone = 0.6f;  // r > 1.5 tan 0.6 = 1.03 m is dark
  return lamp;
}

TEST(IlluminationLamps, PointLampInAPlanarMirrorMatchesItsImage) {
  const LampOverMirror s(lamp_of(LampKind::point));
  const Accel accel(s.scene);
  const IlluminationMaps maps = trace_illumination(s.scene, accel, IlluminationParams{});
  ASSERT_GT(maps.width, 0);
  const MapError e = ceiling_error(s, maps, everywhere);
  std::printf("point lamp via mirror: mean error %.4f, worst %.4f (%llu rays)\n", e.mean, e.worst,
              static_cast<unsigned long long>(maps.stats.illumination_rays));
  // Measured: mean 0.19%, worst 0.57% (3.1e6 rays, 0.1 m texels).
  EXPECT_LT(e.mean, 0.01);
  EXPECT_LT(e.worst, 0.03);
  // The feelers kept the rays to the half of the sphere that sees the mirror.
  EXPECT_LT(maps.stats.zones_traced, maps.stats.zones_total);
}

TEST(IlluminationLamps, SpotInAPlanarMirrorHasItsConesFalloff) {
  LampOverMirror s(lamp_of(LampKind::spot));
  // The falloff's curvature: bilinear reads of 0.1 m texels were 7% off across the ramp
  // (f'' h^2 / 8 ~ 0.017 on values ~0.1-0.5 of the axis'); at 2.5 cm 16x less.
  s.scene.meshes[1].bake.texel_size = 0.025f;
  const Accel accel(s.scene);
  const IlluminationMaps maps = trace_illumination(s.scene, accel, IlluminationParams{});
  ASSERT_GT(maps.width, 0);
  auto radius = [](vec3 p) { return std::hypot(p.x, p.y); };
  // Inside the inner cone (a texel and a half from its edge): the point lamp's closed form.
  const MapError inner = ceiling_error(s, maps, [&](vec3 p) { return radius(p) < 0.48f; });
  // Across the falloff, away from both edges, where the map changes fastest: looser.
  const MapError ramp =
      ceiling_error(s, maps, [&](vec3 p) { return radius(p) > 0.7f && radius(p) < 0.9f; });
  // Well outside the outer cone (r > 1.03 m + 2 texels): no light at all.
  float outside = 0.0f;
  for (vec3 p : {vec3(0.85f, 0.85f, 1), vec3(-0.85f, 0.85f, 1), vec3(0.9f, -0.9f, 1)})
    outside = std::max(outside, test::map_at(maps, s.scene, 1, p).x);
  std::printf(
      "spot via mirror: inner cone mean %.4f worst %.4f; falloff mean %.4f worst %.4f; "
      "outside max %g\n",
      inner.mean, inner.worst, ramp.mean, ramp.worst, double(outside));
  // Measured: inner mean 0.03%, worst 0.11%; falloff mean 0.58%, worst 1.6%.
  EXPECT_LT(inner.mean, 0.01);
  EXPECT_LT(inner.worst, 0.03);
  EXPECT_LT(ramp.mean, 0.02);
  EXPECT_LT(ramp.worst, 0.05);
  EXPECT_EQ(outside, 0.0f);
}

// The sun at 30 degrees from the vertical onto the mirror (sun_over_mirror.h): the ceiling
// gets R E cos 30 everywhere.
TEST(IlluminationLamps, SunInAPlanarMirrorGivesUniformLight) {
  const test::SunOverMirror s;
  const Scene& scene = s.scene;
  const float reflectance = s.reflectance, irradiance = s.irradiance, theta = s.theta;
  const Accel accel(scene);
  const IlluminationMaps maps = trace_illumination(scene, accel, IlluminationParams{});
  ASSERT_GT(maps.width, 0);
  const double expected = reflectance * irradiance * std::cos(theta) / pi;
  const MapError e = map_error(
      maps, scene, {0.6f, -0.85f}, {1.35f, 0.85f}, 1.0f, [&](vec3) { return expected; },
      everywhere);
  std::printf("sun via mirror: mean error %.4f, worst %.4f (expected %.5f)\n", e.mean, e.worst,
              expected);
  // Measured: mean 0.00%, worst 0.02% (parallel rays through a plane: no noise to speak of).
  EXPECT_LT(e.mean, 0.01);
  EXPECT_LT(e.worst, 0.03);
}

// A constant sky L, a vertical 2 x 1 m mirror (x = 0, facing +x) and a floor in front of it
// (x in [0, 2]): every ray a floor point sends into the mirror reflects up into open sky, so
// the sky's light via the mirror is R L times the mirror's projected solid angle, Lambert's
// polygon formula for the mirror's rectangle; stored E / pi.
TEST(IlluminationSky, SkyInAVerticalMirrorMatchesThePolygonFormula) {
  Scene scene;
  const float reflectance = 0.9f, sky = 2.0f;
  const int white = test::add_material(scene, Material{});
  const int shiny = test::add_material(scene, mirror_material(reflectance));
  scene.meshes.push_back(test::make_quad({0, -1, 0}, {0, 2, 0}, {0, 0, 1}, shiny, "mirror"));
  Mesh floor = test::make_quad({0, -1, 0}, {2, 0, 0}, {0, 2, 0}, white, "floor");
  floor.bake.texel_size = 0.1f;
  scene.meshes.push_back(floor);
  scene.sky = Sky{vec3(sky), -1};
  const Accel accel(scene);
  IlluminationParams params;
  params.sky_directions_side = 32;  // 1024 directions: the test's smooth closed form
  const IlluminationMaps maps = trace_illumination(scene, accel, params);
  ASSERT_GT(maps.width, 0);
  const std::vector<glm::dvec3> mirror = {{0, -1, 0}, {0, 1, 0}, {0, 1, 1}, {0, -1, 1}};
  const MapError e = map_error(
      maps, scene, {0.25f, -0.75f}, {1.75f, 0.75f}, 0.0f,
      [&](vec3 p) {
        return reflectance * test::polygon_irradiance(mirror, glm::dvec3(p), {0, 0, 1}, sky) / pi;
      },
      everywhere);
  const double mean = e.mean, worst = e.worst, map_sum = e.map_sum, expected_sum = e.expected_sum;
  std::printf(
      "sky via mirror: mean error %.4f, worst %.4f, region sum ratio %.4f (%llu rays, "
      "%llu feelers)\n",
      mean, worst, map_sum / expected_sum,
      static_cast<unsigned long long>(maps.stats.illumination_rays),
      static_cast<unsigned long long>(maps.stats.feeler_rays));
  // The region's light is unbiased: measured 0.6% off.
  EXPECT_NEAR(map_sum / expected_sum, 1.0, 0.015);
  // Rays saved count each direction at its own density: all of them traced would have cost
  // 1024 x 36 zones x (8 sub-zones x 2 rays)^2.
  EXPECT_EQ(maps.stats.rays_saved, int64_t(1024) * 36 * 16 * 16 -
                                       int64_t(maps.stats.illumination_rays) -
                                       int64_t(maps.stats.feeler_rays));
  // Pointwise the error is the direction sampling's: where the mirror looks small (the far
  // corner, ~0.1 sr projected) only ~12 of the 1024 directions light a point, each with a
  // sharp-edged image of the mirror. Measured: mean 2.7%, worst 25%.
  EXPECT_LT(mean, 0.04);
  EXPECT_LT(worst, 0.35);
}

// ---- energy per light kind -------------------------------------------------------------------
class IlluminationEnergy : public testing::TestWithParam<int> {};

TEST_P(IlluminationEnergy, SentIsDepositedAbsorbedEscapedOrDirect) {
  // Floor, wall, mirror, glass box, glossy plate (test_radiosity's open scene); y up; one light
  // of the kind.
  Scene scene = test::make_open_scene(false);
  const LampKind kinds[] = {LampKind::point, LampKind::spot, LampKind::directional};
  const char* names[] = {"point", "spot", "directional", "sky", "spot with range", "sky image"};
  const int kind = GetParam();
  if (kind == 3) {
    scene.sky = Sky{vec3(0.4f, 0.5f, 0.7f), -1};
  } else if (kind == 5) {
    test::add_sky_image(scene);
  } else {
    Lamp lamp;
    lamp.kind = kinds[kind == 4 ? 1 : kind];
    lamp.position = vec3(0.3f, 1.8f, 0.2f);
    lamp.direction = glm::normalize(vec3(0.2f, -1, 0.1f));
    lamp.intensity = vec3(3.0f, 2.0f, 1.0f);
    lamp.inner_cone = 0.3f;
    lamp.outer_cone = 0.7f;
    if (kind == 4) lamp.range = 2.0f;
    scene.lights.push_back(lamp);
  }
  const LightSources sources(scene);
  const Accel accel(scene);
  IlluminationParams params;
  params.rays_per_zone_side = 48;
  params.sky_directions_side = kind == 5 ? 16 : 4;
  params.trace_all_zones = true;  // so the whole power is sent
  const IlluminationStats s = trace_illumination(scene, accel, params).stats;
  std::printf(
      "%s: sent %.6g W (light %.6g; blue %.6g of %.6g), deposited %.4g, absorbed %.4g, "
      "escaped %.4g, direct %.4g\n",
      names[kind], double(s.power_sent.x), double(sources.power(0).x), double(s.power_sent.z),
      double(sources.power(0).z), double(s.power_deposited.x), double(s.power_absorbed.x),
      double(s.power_escaped.x), double(s.power_direct.x));
  for (int c = 0; c < 3; ++c) {
    // Constant intensities send exactly the light's power; a spot's rays carry its falloff
    // (a stratified estimate of its integral, measured within 1e-4); the sky image's 256
    // directions are drawn by luminance, so each channel's sum is an estimate (measured red
    // +0.1%, blue -1.1%; 16 directions: blue 34% off).
    const double tolerance = kind == 5 ? 0.03 : kind == 1 || kind == 4 ? 1e-3 : 1e-5;
    EXPECT_NEAR(s.power_sent[c] / sources.power(0)[c], 1.0, tolerance);
    const double balance =
        double(s.power_deposited[c]) + s.power_absorbed[c] + s.power_escaped[c] + s.power_direct[c];
    EXPECT_NEAR(balance / s.power_sent[c], 1.0, 1e-5);
    EXPECT_GT(s.power_deposited[c], 0.0f);  // caustics reached the floor or the wall
  }
}

INSTANTIATE_TEST_SUITE_P(Kinds, IlluminationEnergy, testing::Values(0, 1, 2, 3, 4, 5));

// ---- the aimed feelers' inverse maps -------------------------------------------------------
// square_towards must invert LightSources::emit's maps (they live in another file): a ray's
// own square point comes back from any point along it.
TEST(IlluminationLamps, SquareTowardsInvertsTheEmittedRays) {
  Scene scene;
  scene.meshes.push_back(test::make_quad({-1, 0, -1}, {0, 0, 2}, {2, 0, 0},
                                         test::add_material(scene, Material{}), "floor"));
  Lamp point;
  point.position = vec3(0.2f, 1, 0.1f);
  point.intensity = vec3(1.0f);
  Lamp spot = point;
  spot.kind = LampKind::spot;
  spot.direction = glm::normalize(vec3(0.3f, -1, 0.2f));
  spot.outer_cone = 0.9f;
  Lamp sun = point;
  sun.kind = LampKind::directional;
  sun.direction = glm::normalize(vec3(-0.2f, -1, 0.4f));
  scene.lights = {point, spot, sun};
  scene.sky = Sky{vec3(1.0f), -1};
  const LightSources sources(scene);
  std::vector<illumination::LightSetup> setups = {illumination::setup_lamp(sources, 0),
                                                  illumination::setup_lamp(sources, 1),
                                                  illumination::setup_lamp(sources, 2)};
  setups.push_back(illumination::setup_sky_direction(sources, 3, {0.3f, 0.7f}, 1));
  Rng rng(7);
  for (size_t k = 0; k < setups.size(); ++k)
    for (int i = 0; i < 200; ++i) {
      const vec2 u = rng.next_2d() * 0.98f + 0.01f;
      const Ray ray = illumination::light_ray(scene, setups[k], u, rng.next_2d());
      vec2 back;
      ASSERT_TRUE(illumination::square_towards(setups[k], ray.origin + 1.5f * ray.direction, back))
          << "setup " << k;
      EXPECT_NEAR(back.x, u.x, 2e-4) << "setup " << k;
      EXPECT_NEAR(back.y, u.y, 2e-4) << "setup " << k;
    }
  // Outside a spot's outer cone there is no ray.
  vec2 u;
  EXPECT_FALSE(illumination::square_towards(setups[1], spot.position - 2.0f * spot.direction, u));
}

// ---- aimed feelers ----------------------------------------------------------------------------
// A 2 cm mirror ball 1.5 m below a point lamp (1/5000 of a zone of the sphere) or under the
// sun (2e-4 of the scene's disk): the 144 grid feelers miss it, the aimed ones find it, and
// the traced sub-zones carry all its light (same deposited power as tracing every zone).
TEST(IlluminationLamps, AimedFeelersFindASmallBall) {
  for (LampKind kind : {LampKind::point, LampKind::directional}) {
    Scene scene;
    const int white = test::add_material(scene, Material{});
    const int shiny = test::add_material(scene, mirror_material(0.9f));
    scene.meshes.push_back(test::make_quad({-1, -1, 0}, {2, 0, 0}, {0, 2, 0}, white, "floor"));
    scene.meshes.push_back(
        test::make_sphere({0.3f, 0.2f, 0.5f}, 0.02f, 12, 24, shiny, false, "ball"));
    Lamp lamp;
    lamp.kind = kind;
    lamp.position = vec3(0, 0, 2);
    lamp.direction = vec3(0, 0, -1);
    lamp.intensity = vec3(20.0f);
    scene.lights.push_back(lamp);
    const Accel accel(scene);
    IlluminationParams params;
    params.rays_per_zone_side = 128;
    const IlluminationMaps found = trace_illumination(scene, accel, params);
    params.trace_all_zones = true;
    const IlluminationMaps reference = trace_illumination(scene, accel, params);
    params.trace_all_zones = false;
    params.aimed_feelers_side = 0;
    const IlluminationMaps grid_only = trace_illumination(scene, accel, params);
    const char* name = kind == LampKind::point ? "point" : "sun";
    std::printf("%s: %llu of 36 zones traced, deposited %.5g W (all zones %.5g W)\n", name,
                static_cast<unsigned long long>(found.stats.zones_traced),
                double(found.stats.power_deposited.x), double(reference.stats.power_deposited.x));
    EXPECT_GT(found.stats.zones_traced, 0u) << name;
    EXPECT_LE(found.stats.zones_traced, 9u) << name;  // its zone and the 8 around it at most
    ASSERT_GT(reference.stats.power_deposited.x, 0.0f) << name;
    EXPECT_NEAR(found.stats.power_deposited.x / reference.stats.power_deposited.x, 1.0, 0.05)
        << name;
    EXPECT_EQ(grid_only.stats.zones_traced, 0u) << name << ": the grid found it by luck";
  }
}

// ---- determinism -----------------------------------------------------------------------------
TEST(IlluminationLamps, SameBitsWithOneAndTwoThreads) {
  LampOverMirror s(lamp_of(LampKind::spot));
  s.scene.lights.push_back(lamp_of(LampKind::point));
  s.scene.lights.back().position = vec3(0.3f, 0.2f, 0.4f);
  s.scene.lights.back().intensity = vec3(1.0f);
  s.scene.sky = Sky{vec3(0.3f), -1};
  const Accel accel(s.scene);
  IlluminationParams params;
  params.rays_per_zone_side = 96;
  params.sky_directions_side = 3;
  auto bake = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
    return trace_illumination(s.scene, accel, params);
  };
  const IlluminationMaps one = bake(1), two = bake(2);
  ASSERT_GT(one.stats.power_deposited.x, 0.0f);
  EXPECT_TRUE(test::same_bits(one.radiance, two.radiance));
  EXPECT_EQ(one.stats.illumination_rays, two.stats.illumination_rays);
  params.seed = 5;  // another seed gives other noise: the comparison above can fail
  EXPECT_FALSE(test::same_bits(one.radiance, bake(2).radiance));
}

}  // namespace
}  // namespace lb

namespace lb {
namespace {

// One specular step for every ray tracer (bump.h, specular_normal): a flat mirror whose normal
// map tilts its normal by 20 degrees about y bakes the caustic of the tilted normal, as HQ
// mode renders it (before, pass 1 reflected about the flat normal). Against an independent
// quadrature: rays from the lamp to a fine grid of mirror points, reflected about the tilted
// normal, binned on the ceiling in 0.2 m cells.
TEST(IlluminationLamps, BumpMappedMirrorBakesTheCausticOfItsBumps) {
  const float tilt = glm::radians(20.0f);
  const vec3 tilted(std::sin(tilt), 0.0f, std::cos(tilt));
  LampOverMirror s(lamp_of(LampKind::point));
  s.scene.textures.push_back(test::make_rgb_texture(
      1, 1, [&](int, int) { return 0.5f * (tilted + 1.0f); }, "tilted normal map"));
  Material& mirror = s.scene.materials[size_t(s.scene.meshes[0].material)];
  mirror.bump = BumpKind::normal_map;
  mirror.bump_texture = 0;
  const Accel accel(s.scene);
  const IlluminationMaps maps = trace_illumination(s.scene, accel, IlluminationParams{});

  // Quadrature: mirror points on an n x n grid over [-1, 1]^2 (z = 0), each sending the lamp's
  // I cos / d^2 dA, reflected about the tilted normal, onto the ceiling z = 1.
  constexpr int cells = 8;  // 0.2 m over [-0.8, 0.8]^2
  std::vector<double> power(cells * cells, 0.0);
  const int n = 2000;
  const double da = (2.0 / n) * (2.0 / n);
  const glm::dvec3 lamp(0, 0, 0.5), normal(tilted);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const glm::dvec3 m(-1.0 + (i + 0.5) * 2.0 / n, -1.0 + (j + 0.5) * 2.0 / n, 0.0);
      const glm::dvec3 d = m - lamp;
      const double d2 = glm::dot(d, d), cos_mirror = 0.5 / std::sqrt(d2);
      const glm::dvec3 in = d / std::sqrt(d2);
      const glm::dvec3 out = in - 2.0 * glm::dot(in, normal) * normal;
      if (out.z <= 0.0) continue;
      const glm::dvec3 c = m + out * (1.0 / out.z);
      const int cx = int(std::floor((c.x + 0.8) / 0.2)), cy = int(std::floor((c.y + 0.8) / 0.2));
      if (cx < 0 || cy < 0 || cx >= cells || cy >= cells) continue;
      power[size_t(cy * cells + cx)] += s.reflectance * s.intensity * cos_mirror / d2 * da;
    }
  double mean_error = 0.0, worst = 0.0, flat_difference = 0.0;
  for (int cy = 0; cy < cells; ++cy)
    for (int cx = 0; cx < cells; ++cx) {
      const double expected = power[size_t(cy * cells + cx)] / (0.2 * 0.2) / pi;  // E / pi
      double baked = 0.0;
      for (int a = 0; a < 8; ++a)
        for (int b = 0; b < 8; ++b) {
          const vec3 p(-0.8f + 0.2f * (float(cx) + (float(a) + 0.5f) / 8.0f),
                       -0.8f + 0.2f * (float(cy) + (float(b) + 0.5f) / 8.0f), 1.0f);
          baked += test::map_at(maps, s.scene, 1, p).x / 64.0;
        }
      const double error = std::abs(baked / expected - 1.0);
      mean_error += error / (cells * cells);
      worst = std::max(worst, error);
      const vec3 centre(-0.7f + 0.2f * float(cx), -0.7f + 0.2f * float(cy), 1.0f);
      flat_difference = std::max(flat_difference, std::abs(s.expected(centre) / expected - 1.0));
    }
  std::printf(
      "bump-mapped mirror caustic vs quadrature: mean %.4f, worst %.4f; the flat "
      "mirror's would be off by up to %.3f\n",
      mean_error, worst, flat_difference);
  EXPECT_LT(mean_error, 0.02);
  EXPECT_LT(worst, 0.06);
  EXPECT_GT(flat_difference, 0.15);  // the test can tell the bumps from the flat mirror
}

}  // namespace
}  // namespace lb
