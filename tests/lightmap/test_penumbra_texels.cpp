// The export's direct term in a penumbra (issue 36), against the closed form of a square light
// over a floor with a square plate between them (Lambert's formula for the light less the
// plate's projection onto it): a penumbra ten texels wide at 10 texels/m, read back the way an
// engine reads the map.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
#include <glm/gtc/constants.hpp>
#include <tbb/global_control.h>

#include "bake/lightmap/lightmap.h"
#include "bake/pipeline/bake.h"
#include "map_read_back.h"
#include "test_helpers.h"

namespace lb {
namespace {

// A black 4 x 4 m floor (nothing bounces) under a 1 x 1 m light at 1 m facing down, radiance
// kL, and a black 0.6 x 0.6 m plate at 0.5 m, off-centre, whose shadow has a wide penumbra.
constexpr double kL = 2.0;
constexpr double kLightY = 1.0, kPlateY = 0.5;
constexpr double kLight[4] = {-0.5, 0.5, -0.5, 0.5};  // x0, x1, z0, z1
constexpr double kPlate[4] = {0.0, 0.6, -0.3, 0.3};

// A black material (nothing bounces); its index.
int add_black(Scene& scene) {
  Material black;
  black.reflectance = vec3(0.0f);
  return test::add_material(scene, black);
}

// The 1 x 1 m light at kLightY facing down, radiance kL.
void add_light(Scene& scene) {
  Material light;
  light.reflectance = vec3(0.0f);
  light.emission = vec3(float(kL));
  const int l = test::add_material(scene, light);
  scene.meshes.push_back(test::make_quad({float(kLight[0]), float(kLightY), float(kLight[2])},
                                         {1, 0, 0}, {0, 0, 1}, l, "light"));
}

Scene plate_over_floor() {
  Scene scene;
  const int b = add_black(scene);
  scene.meshes.push_back(test::make_quad({-2, 0, 2}, {4, 0, 0}, {0, 0, -4}, b, "floor"));
  add_light(scene);
  scene.meshes.push_back(test::make_quad({float(kPlate[0]), float(kPlateY), float(kPlate[2])},
                                         {0.6f, 0, 0}, {0, 0, 0.6f}, b, "plate"));
  return scene;
}

// Lambert's formula: irradiance at p (normal +y) from the rectangle [x0,x1] x [z0,z1] at
// height y of radiance kL, E = L/2 sum_k theta_k (n . unit(v_k x v_k+1)).
double rectangle_irradiance_at(glm::dvec3 p, double x0, double x1, double z0, double z1, double y) {
  if (x1 <= x0 || z1 <= z0) return 0.0;
  const std::array<glm::dvec3, 4> corners = {glm::dvec3(x0, y, z0), glm::dvec3(x1, y, z0), glm::dvec3(x1, y, z1),
                                        glm::dvec3(x0, y, z1)};
  double sum = 0.0;
  for (size_t k = 0; k < 4; ++k) {
    const glm::dvec3 a = glm::normalize(corners[k] - p), b = glm::normalize(corners[(k + 1) % 4] - p);
    const double theta = std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0));
    sum += theta * glm::normalize(glm::cross(a, b)).y;
  }
  return kL / 2.0 * std::abs(sum);
}

// E / pi at floor point p: the light less the part of it the plate hides, which is the plate
// projected from p onto the light's plane (scale kLightY / kPlateY about p) clipped to it.
double plate_closed_form(vec3 point) {
  const glm::dvec3 p(point.x, 0.0, point.z);
  const double s = kLightY / kPlateY;
  const double x0 = std::max(kLight[0], p.x + s * (kPlate[0] - p.x));
  const double x1 = std::min(kLight[1], p.x + s * (kPlate[1] - p.x));
  const double z0 = std::max(kLight[2], p.z + s * (kPlate[2] - p.z));
  const double z1 = std::min(kLight[3], p.z + s * (kPlate[3] - p.z));
  const double all = rectangle_irradiance_at(p, kLight[0], kLight[1], kLight[2], kLight[3], kLightY);
  return (all - rectangle_irradiance_at(p, x0, x1, z0, z1, kLightY)) / glm::pi<double>();
}

struct PlateMapError {
  double mre = 0.0;           // mean |map - closed form| / closed form where the floor is lit
  double energy_ratio = 0.0;  // the map's mean over the floor / the closed form's
};

PlateMapError plate_map_error(const Scene& scene, const BakeResult& bake, const Lightmap& map) {
  double error = 0.0, map_sum = 0.0, exact_sum = 0.0;
  size_t count = 0;
  const double peak = plate_closed_form(vec3(-1.0f, 0.0f, 0.0f));  // lit, near the light's foot
  for (const MapReadPoint& p : read_back(scene, bake, map, 0, 4000.0f)) {
    const double exact = plate_closed_form(p.position);
    map_sum += p.value.x, exact_sum += exact;
    if (exact < 0.05 * peak) continue;  // the far floor and the umbra's core: relative noise
    error += std::abs(double(p.value.x) - exact) / exact;
    ++count;
  }
  return {error / double(std::max<size_t>(count, 1)), map_sum / exact_sum};
}

// The map baked on 1 and on 2 threads (they must have the same bits).
std::pair<Lightmap, Lightmap> on_one_and_two_threads(const Scene& scene, const BakeResult& bake,
                                                     const LightmapParams& params) {
  std::pair<Lightmap, Lightmap> maps;
  {
    const tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    maps.first = bake_lightmap(scene, bake, params);
  }
  const tbb::global_control two(tbb::global_control::max_allowed_parallelism, 2);
  maps.second = bake_lightmap(scene, bake, params);
  return maps;
}

// The direct term at the automatic number of shadow rays (16 a cell side here: the Cornell
// box's at game densities) and at a quarter of them. Measured: 0.71% and 1.44% mean relative
// error, energy +0.03% and +0.24%. (A joint bilateral filter on the ratio estimator's shadow
// share, guided by texel position and normal, took the quarter only to 1.35% at its best: the
// error at 8 a side is mostly the projection's fit of few points, not the share's noise.)
TEST(PenumbraTexels, AreaLightAndPlateAgainstTheClosedFormAtTenTexelsPerMetre) {
  const Scene scene = plate_over_floor();
  const BakeResult bake = bake_scene(scene, bake_at(10.0f));
  LightmapParams params;
  params.contents = LightmapContents::all;
  const Lightmap automatic = bake_lightmap(scene, bake, params);
  params.direct_side = 8;
  const Lightmap quarter = bake_lightmap(scene, bake, params);
  const PlateMapError full_error = plate_map_error(scene, bake, automatic);
  const PlateMapError quarter_error = plate_map_error(scene, bake, quarter);
  std::printf("MRE against the closed form: automatic %.4f (energy %.5f), 8 a side %.4f (%.5f)\n",
              full_error.mre, full_error.energy_ratio, quarter_error.mre,
              quarter_error.energy_ratio);
  RecordProperty("automatic_mre", std::to_string(full_error.mre));
  RecordProperty("quarter_mre", std::to_string(quarter_error.mre));
  EXPECT_TRUE(automatic.ratio_estimator);
  EXPECT_LE(full_error.mre, 0.01);
  EXPECT_NEAR(full_error.energy_ratio, 1.0, 0.002);
  EXPECT_LE(quarter_error.mre, 0.02);
  EXPECT_NEAR(quarter_error.energy_ratio, 1.0, 0.005);
}

// Open Image Denoise on the shadow share of the penumbra's texels (LightmapParams::
// denoise_direct; its library from build/pypi, which scripts/test.sh fills: without it this
// test fails, never skips). Measured at 8 points a cell side (a quarter of the automatic 16):
// 0.96% mean relative error against 1.44% undenoised, energy +0.23% (+0.24% undenoised). The
// issue's target, a quarter of the rays denoised within the automatic's 0.71%, is not met; the
// mean of 16 seeds' undenoised maps at 8 is 0.47% off, so what is left is noise OIDN keeps.
TEST(PenumbraTexels, DenoisedQuarterOfTheRaysAgainstTheClosedForm) {
  const Scene scene = plate_over_floor();
  const BakeResult bake = bake_scene(scene, bake_at(10.0f));
  LightmapParams params;
  params.contents = LightmapContents::all;
  params.direct_side = 8;
  const PlateMapError plain = plate_map_error(scene, bake, bake_lightmap(scene, bake, params));
  params.denoise_direct = true;
  const auto [one_thread, two_threads] = on_one_and_two_threads(scene, bake, params);
  const PlateMapError denoised = plate_map_error(scene, bake, one_thread);
  std::printf("8 a side: MRE %.4f undenoised, %.4f denoised (energy %.5f, OIDN's own %.5f)\n",
              plain.mre, denoised.mre, denoised.energy_ratio, one_thread.denoise.energy_ratio);
  RecordProperty("denoised_quarter_mre", std::to_string(denoised.mre));
  ASSERT_TRUE(one_thread.denoised);
  EXPECT_GT(one_thread.denoise.texels, 100u);   // the penumbra's
  EXPECT_LT(one_thread.denoise.texels, 1972u);  // of the floor's covered texels
  EXPECT_LE(denoised.mre, 0.8 * plain.mre);
  EXPECT_LE(denoised.mre, 0.011);
  EXPECT_NEAR(denoised.energy_ratio, 1.0, 0.005);
  EXPECT_NEAR(one_thread.denoise.energy_ratio, 1.0, 0.005);
  // The same bits whatever the thread count (OIDN's CPU device included, on one machine).
  EXPECT_EQ(one_thread.radiance, two_threads.radiance);
}

// The target read as a quarter of the shadow rays: every one of the automatic 16 x 16
// points a cell still places the texels' fit (LightmapParams::shadow_side), but only a quarter
// of the rays are traced, so the ratio estimator's share carries their noise and none of the
// fit's error. Spread evenly (8 x 8 a cell) or where the shadows are (adaptive_shadow_rays, the
// default: a 4 x 4 pilot, then the cells it finds in a penumbra and their neighbours, 4 x 4 to
// 16 x 16 each by the pilot's lit share around them, the pilot's rays counted too; this
// penumbra is wide, 47% of the pilot's rays; shadow_plan.h). Measured: all the rays 0.71%; a
// quarter evenly 1.31% undenoised, 0.81% denoised; adaptively 0.87% and 0.67%; energy +0.13%
// and +0.13%. The target: a quarter denoised no worse than all the rays undenoised,
// energy within 0.5%.
TEST(PenumbraTexels, DenoisedQuarterOfTheShadowRaysAgainstAllOfThem) {
  const Scene scene = plate_over_floor();
  const BakeResult bake = bake_scene(scene, bake_at(10.0f));
  LightmapParams params;
  params.contents = LightmapContents::all;
  const Lightmap all_rays = bake_lightmap(scene, bake, params);
  params.shadow_side = 8;
  params.adaptive_shadow_rays = false;
  const Lightmap evenly = bake_lightmap(scene, bake, params);
  params.adaptive_shadow_rays = true;
  const Lightmap quarter = bake_lightmap(scene, bake, params);
  params.denoise_direct = true;
  const auto [one_thread, two_threads] = on_one_and_two_threads(scene, bake, params);
  const PlateMapError full = plate_map_error(scene, bake, all_rays);
  const PlateMapError even = plate_map_error(scene, bake, evenly);
  const PlateMapError plain = plate_map_error(scene, bake, quarter);
  const PlateMapError denoised = plate_map_error(scene, bake, one_thread);
  std::printf("all rays %.4f; a quarter evenly %.4f, adaptively: %.4f undenoised, %.4f denoised "
              "(energy %.5f, %.5f)\n",
              full.mre, even.mre, plain.mre, denoised.mre, plain.energy_ratio,
              denoised.energy_ratio);
  RecordProperty("quarter_rays_denoised_mre", std::to_string(denoised.mre));
  for (const Lightmap* map : {&evenly, &quarter})
    EXPECT_LE(4 * map->shadow_rays, all_rays.shadow_rays + all_rays.shadow_rays / 50);
  EXPECT_LE(plain.mre, 0.9 * even.mre);  // the rays where the noise is
  EXPECT_LE(denoised.mre, full.mre);      // the target (0.67% against 0.71%)
  EXPECT_LE(denoised.mre, 0.85 * plain.mre);
  EXPECT_NEAR(denoised.energy_ratio, 1.0, 0.005);
  EXPECT_NEAR(plain.energy_ratio, 1.0, 0.005);
  EXPECT_EQ(one_thread.radiance, two_threads.radiance);
}

// The floor under the light alone, baked: no penumbra anywhere.
std::pair<Scene, BakeResult> without_the_plate() {
  Scene scene = plate_over_floor();
  scene.meshes.pop_back();  // the plate
  BakeResult bake = bake_scene(scene, bake_at(10.0f));
  return {std::move(scene), std::move(bake)};
}

// Adaptive shadow rays spend none where the pilot saw no shadow: without the plate every cell
// is lit, so a quarter of the rays adaptively is the pilot alone (a sixteenth of all of them)
// and the map is the closed form's, exactly as evenly spread rays give it.
TEST(PenumbraTexels, AdaptiveRaysSpendNothingWhereNoShadowFalls) {
  const auto [scene, bake] = without_the_plate();
  LightmapParams params;
  params.contents = LightmapContents::all;
  params.shadow_side = 8;
  params.adaptive_shadow_rays = false;
  const Lightmap evenly = bake_lightmap(scene, bake, params);
  params.adaptive_shadow_rays = true;
  const Lightmap adaptive = bake_lightmap(scene, bake, params);
  EXPECT_EQ(4 * adaptive.shadow_rays, evenly.shadow_rays);
  EXPECT_EQ(adaptive.radiance, evenly.radiance);
}

// A black wall in the plane x = -0.2 facing -x, under the light, which straddles its plane: from
// the wall, 70% of the light's surface lies behind it. Nothing casts a shadow, so the ratio
// estimator makes every texel the closed form (unshadowed_light.h) with all the rays. At the
// automatic density's sides (4 x 4 points a cell, a quarter of the rays: a pilot of one ray a
// cell) the adaptive plan keeps every cell's lit verdict, and a verdict's share must be 1 too,
// whatever its one ray's point on the light: it is estimated from every point of the cell, not
// the pilot's one, which lies behind the wall 70% of the time (measured with the pilot's point:
// 67 of the 241 lit texels 0, those whose four cells all drew such a point).
TEST(PenumbraTexels, LitVerdictsKeepTheClosedFormWhereTheLightStraddlesTheHorizon) {
  Scene scene;
  const int b = add_black(scene);
  scene.meshes.push_back(test::make_quad({-0.2f, 0, -1}, {0, 0, 2}, {0, 0.9f, 0}, b, "wall"));
  add_light(scene);
  const BakeResult bake = bake_scene(scene, bake_at(10.0f));
  LightmapParams params;
  params.contents = LightmapContents::all;
  params.direct_side = 4;
  const Lightmap all_rays = bake_lightmap(scene, bake, params);
  params.shadow_side = 2;
  const Lightmap quarter = bake_lightmap(scene, bake, params);
  ASSERT_TRUE(all_rays.ratio_estimator);
  size_t lit = 0, differ = 0, dark = 0;
  for (size_t k = 0; k < all_rays.direct_term.size(); ++k) {
    lit += all_rays.direct_term[k].x > 0.0f;
    differ += quarter.direct_term[k] != all_rays.direct_term[k];
    dark += all_rays.direct_term[k].x > 0.0f && quarter.direct_term[k].x == 0.0f;
  }
  std::printf("%zu lit texels: %zu differ from all the rays', %zu of them dark\n", lit, differ,
              dark);
  EXPECT_GT(lit, 150u);  // the wall's texels (241 measured)
  EXPECT_EQ(differ, 0u);
  EXPECT_EQ(quarter.radiance, all_rays.radiance);
  EXPECT_LT(8 * quarter.shadow_rays, all_rays.shadow_rays);  // the pilot's alone
}

// Without the plate the floor has no penumbra: every share is 1 (exact), so --denoise changes
// no bit and OIDN is not run.
TEST(PenumbraTexels, DenoiseLeavesAnUnshadowedFloorBitForBit) {
  const auto [scene, bake] = without_the_plate();
  LightmapParams params;
  params.contents = LightmapContents::all;
  params.direct_side = 8;
  const Lightmap plain = bake_lightmap(scene, bake, params);
  params.denoise_direct = true;
  const Lightmap denoised = bake_lightmap(scene, bake, params);
  EXPECT_TRUE(denoised.denoised);
  EXPECT_EQ(denoised.denoise.texels, 0u);
  EXPECT_EQ(plain.radiance, denoised.radiance);
}

}  // namespace
}  // namespace lb
