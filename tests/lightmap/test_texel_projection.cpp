// The direct term's texels fitted to bilinear filtering (texel_projection.h, issue 36), against
// the closed form of a point lamp over a floor, read back the way an engine reads the map, with
// the tent means as the control.

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <cstring>
#include <glm/gtc/constants.hpp>

#include "bake/lightmap/lightmap.h"
#include "bake/lightmap/texel_footprint.h"
#include "bake/pipeline/bake.h"
#include "map_read_back.h"
#include "test_helpers.h"

namespace lb {
namespace {

// A black 4 x 4 m floor (nothing bounces) under a point lamp 0.5 m above its middle, intensity
// pi W/sr: the map holds E / pi = h / d^3 (1/m^2 x m = W/(sr m^2) at 1 W/sr), 4 at the lamp's
// foot, a peak about ten texels wide at 10 texels/m.
constexpr float kLampHeight = 0.5f;

Scene lamp_over_floor() {
  Scene scene = black_floor();
  Lamp lamp;
  lamp.kind = LampKind::point;
  lamp.position = vec3(0.0f, kLampHeight, 0.0f);
  lamp.intensity = vec3(glm::pi<float>());
  scene.lights.push_back(lamp);
  return scene;
}

double closed_form(vec3 p) {
  const double r2 = double(p.x) * p.x + double(p.z) * p.z, h = kLampHeight;
  return h / std::pow(r2 + h * h, 1.5);
}

struct FitError {
  double mre = 0.0;          // mean |map - closed form| / closed form, within 1.5 m of the foot
  double energy_ratio = 0.0;  // the map's mean over the floor / the closed form's
};

FitError fit_error(const Scene& scene, const BakeResult& bake, const Lightmap& map) {
  double error = 0.0, map_sum = 0.0, exact_sum = 0.0;
  size_t count = 0;
  for (const MapReadPoint& p : read_back(scene, bake, map, 0, 4000.0f)) {
    const double exact = closed_form(p.position);
    map_sum += p.value.x, exact_sum += exact;
    if (p.position.x * p.position.x + p.position.z * p.position.z > 1.5f * 1.5f) continue;
    error += std::abs(double(p.value.x) - exact) / exact;
    ++count;
  }
  return {error / double(std::max<size_t>(count, 1)), map_sum / exact_sum};
}

LightmapParams direct_params(bool project) {
  LightmapParams params;
  params.contents = LightmapContents::all;
  params.project_direct = project;
  return params;
}

// Measured: 0.19% against 0.75% for the means (whose tent blurs the peak's top and flanks);
// the power the floor holds within 0.02% of the closed form's either way.
TEST(TexelProjection, PointLampFalloffAtTenTexelsPerMetre) {
  const Scene scene = lamp_over_floor();
  const BakeResult bake = bake_scene(scene, bake_at(10.0f));
  const FitError projected = fit_error(scene, bake, bake_lightmap(scene, bake, direct_params(true)));
  const FitError means = fit_error(scene, bake, bake_lightmap(scene, bake, direct_params(false)));
  std::printf("projected: %.4f mean relative error, energy %.5f; tent means: %.4f, %.5f\n",
              projected.mre, projected.energy_ratio, means.mre, means.energy_ratio);
  RecordProperty("projected_mre", std::to_string(projected.mre));
  RecordProperty("means_mre", std::to_string(means.mre));
  EXPECT_LE(projected.mre, 0.5 * means.mre);
  EXPECT_LE(projected.mre, 0.004);
  EXPECT_NEAR(projected.energy_ratio, 1.0, 0.002);
  EXPECT_NEAR(means.energy_ratio, 1.0, 0.002);
}

TEST(TexelProjection, SameBitsWhateverTheThreadCount) {
  const Scene scene = lamp_over_floor();
  const BakeResult bake = bake_scene(scene, bake_at(10.0f));
  const Lightmap all = bake_lightmap(scene, bake, direct_params(true));
  Lightmap one;
  tbb::task_arena(1).execute([&] { one = bake_lightmap(scene, bake, direct_params(true)); });
  ASSERT_EQ(all.radiance.size(), one.radiance.size());
  EXPECT_EQ(std::memcmp(all.radiance.data(), one.radiance.data(),
                        all.radiance.size() * sizeof(vec3)),
            0);
  EXPECT_GT(all.projection.iterations, 0) << "the projection did not run";
}

// The budget rule's sides: the bundled scenes at their automatic density (the Cornell box's
// atlas touches about 147k cells, the rooms' 137k) keep the sides they had before it, game
// densities get more points.
TEST(TexelProjection, SidesFromTheBudget) {
  EXPECT_EQ(side_for_budget(kDirectPointsBudget, 137'000, 4, 16), 4);
  EXPECT_EQ(side_for_budget(kDirectPointsBudget, 3'700, 4, 16), 16);
  EXPECT_EQ(side_for_budget(kDirectPointsBudget, 13'000, 4, 16), 12);
  EXPECT_EQ(side_for_budget(kDirectPointsBudget, 0, 4, 16), 16);
  EXPECT_EQ(side_for_budget(262144.0, 117'000, 1, 8), 1);
  EXPECT_EQ(side_for_budget(262144.0, 3'700, 1, 8), 8);
}

}  // namespace
}  // namespace lb
