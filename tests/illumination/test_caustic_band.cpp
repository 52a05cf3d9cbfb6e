// The caustic map's L1 band (issue 38; IlluminationParams::directional): the sun reflected by a
// planar mirror onto a ceiling arrives from one known direction, so the band decoded at any
// tilted normal (bake/sh_projection.h, s = 1) must follow the cosine law; L0 keeps its bits with
// the band on, and the band has the same bits at 1 and 2 threads.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "bake/bump.h"
#include "bake/illumination/illumination.h"
#include "bake/sh_projection.h"
#include "bake/transport/baked_terms.h"
#include "map_lookup.h"
#include "sun_over_mirror.h"
#include "test_helpers.h"

namespace lb {
namespace {

constexpr float kPif = std::numbers::pi_v<float>;

using test::SunOverMirror;

// The band at point p of the ceiling (mesh 1), read with the map's own bilinear rule.
ShL1 band_at(const IlluminationMaps& maps, const Scene& scene, vec3 p) {
  ShL1 sh;
  sh.l0 = test::map_at(maps, scene, 1, p);
  for (size_t a = 0; a < 3; ++a) {
    IlluminationMaps axis = maps;
    axis.radiance = maps.l1[a];
    sh.l1[a] = test::map_at(axis, scene, 1, p);
  }
  IlluminationMaps share = maps;
  for (size_t k = 0; k < share.radiance.size(); ++k) share.radiance[k] = vec3(maps.l1_share[k]);
  sh.share = test::map_at(share, scene, 1, p).x;
  return sh;
}

TEST(CausticBand, DecodedSunThroughAMirrorFollowsTheCosineLaw) {
  const SunOverMirror s;
  const Accel accel(s.scene);
  IlluminationParams params;
  params.directional = true;
  const IlluminationMaps maps = trace_illumination(s.scene, accel, params);
  ASSERT_GT(maps.width, 0);
  for (const std::vector<vec3>& axis : maps.l1) ASSERT_EQ(axis.size(), maps.radiance.size());
  ASSERT_EQ(maps.l1_share.size(), maps.radiance.size());
  const vec3 n0(0.0f, 0.0f, -1.0f);
  // E(n)/pi = R E max(0, from . n) / pi: normals tilted about y (towards and away from the
  // light, 70 degrees past the horizon of the light: the clamp) and about x.
  std::vector<vec3> normals = {n0};
  for (float deg : {-40.0f, -20.0f, 20.0f, 40.0f, 70.0f}) {
    const float a = deg * kPif / 180.0f;
    normals.push_back({std::sin(a), 0.0f, -std::cos(a)});
  }
  for (float deg : {-30.0f, 30.0f}) {
    const float a = deg * kPif / 180.0f;
    normals.push_back({0.0f, std::sin(a), -std::cos(a)});
  }
  const float scale = s.reflectance * s.irradiance / kPif;
  double worst = 0.0;
  int points = 0;
  for (float x = 0.6f; x <= 1.36f; x += 0.15f)
    for (float y = -0.8f; y <= 0.81f; y += 0.2f) {
      const ShL1 sh = band_at(maps, s.scene, {x, y, 1.0f});
      EXPECT_FLOAT_EQ(sh.share, 1.0f);
      ++points;
      for (const vec3& n : normals) {
        const float expected = scale * std::max(0.0f, glm::dot(s.from(), n));
        const vec3 decoded = decode_directional(sh, n, n0);
        for (int c = 0; c < 3; ++c) {
          const double error = std::abs(double(decoded[c]) - double(expected)) / double(scale);
          worst = std::max(worst, error);
        }
      }
    }
  std::printf("caustic band, sun via mirror: %d points x %zu normals, worst error %.5f of R E/pi\n",
              points, normals.size(), worst);
  // Parallel rays through a plane: every deposit has the same direction, so the band is exact
  // up to float rounding and the filter's sums. Measured: 7e-5 of R E / pi.
  EXPECT_LT(worst, 1e-3);
}

TEST(CausticBand, MapKeepsItsBitsAndTheBandItsBitsAtAnyThreadCount) {
  const SunOverMirror s;
  const Accel accel(s.scene);
  IlluminationParams params;
  const IlluminationMaps plain = trace_illumination(s.scene, accel, params);
  params.directional = true;
  const auto bake = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
    return trace_illumination(s.scene, accel, params);
  };
  const IlluminationMaps one = bake(1), two = bake(2);
  ASSERT_GT(plain.stats.power_deposited.x, 0.0f);
  EXPECT_TRUE(plain.l1[0].empty());
  EXPECT_TRUE(test::same_bits(plain.radiance, one.radiance));
  EXPECT_TRUE(test::same_bits(one.radiance, two.radiance));
  for (size_t a = 0; a < 3; ++a) EXPECT_TRUE(test::same_bits(one.l1[a], two.l1[a]));
  // The band is not all zeros (the comparison above could not fail then): the light's
  // tangential direction is -x.
  double along_x = 0.0;
  for (const vec3& v : one.l1[0]) along_x += double(v.x);
  EXPECT_LT(along_x, 0.0);
}

// HQ's lookup of the map term: on a normal-mapped ceiling the band is taken at the mapped
// normal n (the cosine law R E max(0, from . n) / pi), and without the band the plain map
// (R E cos(theta) / pi whatever n).
TEST(CausticBand, HqLookupTakesTheBandAtTheNormalMapsNormal) {
  SunOverMirror s;
  Texture map;  // one texel: the tangent-space normal (0.7, 0.7, 1), tilted 45 degrees
  map.width = map.height = 1;
  map.channels = 3;
  map.texels = {0.85f, 0.85f, 1.0f};
  s.scene.textures.push_back(map);
  Material bumpy;
  bumpy.bump = BumpKind::normal_map;
  bumpy.bump_texture = 0;
  s.scene.meshes[1].material = test::add_material(s.scene, bumpy);
  const Accel accel(s.scene);
  IlluminationParams params;
  params.directional = true;
  BakeResult bake;
  bake.illumination = trace_illumination(s.scene, accel, params);
  BakedScene baked = make_baked_scene(s.scene, bake);
  ASSERT_TRUE(baked.directional);
  const float scale = s.reflectance * s.irradiance / kPif;
  double worst = 0.0, worst_plain = 0.0, tilt = 0.0, flat_tilt = 0.0;
  for (float x = 0.6f; x <= 1.36f; x += 0.25f)
    for (float y = -0.8f; y <= 0.81f; y += 0.4f) {
      const Ray ray{{x, y, 0.5f}, {0.0f, 0.0f, 1.0f}, 0.0f, 1e30f};
      const std::optional<Hit> hit = accel.intersect(ray);
      ASSERT_TRUE(hit && hit->mesh == 1);
      const SurfacePoint sp = surface_at(baked.scene, *hit, ray);
      const vec3 n = bumped_normal(baked.scene, sp);
      tilt = std::max(tilt, double(std::acos(glm::dot(n, sp.shading_normal))));
      baked.directional = true;
      const float expected = scale * std::max(0.0f, glm::dot(s.from(), n));
      worst = std::max(worst, double(std::abs(illumination_at(baked, sp).y - expected)) / scale);
      // What L0 alone tilted with n would give (the band's L1 = 0): far from the cosine law.
      const float flat = scale * std::cos(s.theta) * glm::dot(n, sp.shading_normal);
      flat_tilt = std::max(flat_tilt, double(std::abs(flat - expected)) / scale);
      baked.directional = false;
      const float plain = scale * std::cos(s.theta);
      worst_plain =
          std::max(worst_plain, double(std::abs(illumination_at(baked, sp).y - plain)) / scale);
    }
  std::printf("caustic band in HQ: normal map %.1f degrees, worst error %.5f (plain %.5f, "
              "L1 = 0 %.3f)\n",
              tilt * 180.0 / kPif, worst, worst_plain, flat_tilt);
  EXPECT_GT(tilt, 0.7);       // 45 degrees
  EXPECT_GT(flat_tilt, 0.1);  // the band's L1 has something to do
  // Measured: 3e-5 and 6e-5 of R E / pi.
  EXPECT_LT(worst, 1e-3);
  EXPECT_LT(worst_plain, 1e-3);
}

}  // namespace
}  // namespace lb
