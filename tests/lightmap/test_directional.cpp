// Directional lightmaps (issue 38; bake/sh_projection.h, directional_lightmap.h,
// bake/io/gltf_directional.h): the band's projection and decode against closed forms (one
// direction, a uniform sky, their sum), de-ringing, the L0 band equal to the plain map bit for
// bit, the direct term's L1 and share on a real bake against Lambert's vector irradiance of the
// light polygon, and the glTF extension's round trip.

#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <functional>
#include <glm/gtc/constants.hpp>
#include <tbb/global_control.h>

#include "bake/bump.h"
#include "bake/export/gltf_bake_read.h"
#include "bake/io/gltf_directional.h"
#include "bake/export/gltf_export.h"
#include "bake/io/height_to_normal.h"
#include "bake/io/scene_load.h"
#include "bake/lightmap/directional_lightmap.h"
#include "bake/sh_projection.h"
#include "bake/pipeline/bake.h"
#include "bake/tangent_space.h"
#include "illumination/sun_over_mirror.h"
#include "test_helpers.h"

namespace lb {
namespace {

constexpr float kPi = glm::pi<float>();

// A uniform sky of radiance L over the hemisphere: E/pi = L, no direction.
TEST(ShProjection, UniformSkyHasNoDirection) {
  const vec3 n0 = glm::normalize(vec3(0.3f, 1.0f, -0.2f));
  const ShL1 sh = project_radiance([](vec3) { return vec3(2.0f, 1.0f, 0.5f); }, n0, 64);
  EXPECT_NEAR(sh.l0.x, 2.0f, 2e-3f);
  EXPECT_NEAR(sh.l0.z, 0.5f, 5e-4f);
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(glm::length(sh.l1[size_t(a)]), 0.0f, 2e-3f);
}

// A cosine lobe about the normal, L = c cos: E/pi = (1/pi) c 2pi/3 = 2c/3, symmetric: no L1.
TEST(ShProjection, CosineLobeAboutTheNormal) {
  const vec3 n0(0.0f, 0.0f, 1.0f);
  const ShL1 sh = project_radiance(
      [&](vec3 w) { return vec3(3.0f * std::max(0.0f, glm::dot(w, n0))); }, n0, 128);
  EXPECT_NEAR(sh.l0.x, 2.0f, 2e-3f);
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(glm::length(sh.l1[size_t(a)]), 0.0f, 2e-3f);
}

// A uniform cap of radiance L and half-angle b about direction d, wholly above the horizon:
// its vector irradiance is pi L sin^2(b) d, so L0 = L sin^2 b (n0 . d) and
// L1 = L sin^2 b (d - n0 (n0 . d)).
TEST(ShProjection, TiltedCapMatchesItsVectorIrradiance) {
  const vec3 n0(0.0f, 0.0f, 1.0f);
  const float theta = glm::radians(40.0f), b = glm::radians(20.0f), L = 5.0f;
  const vec3 d(std::sin(theta), 0.0f, std::cos(theta));
  const ShL1 sh = project_radiance(
      [&](vec3 w) { return vec3(glm::dot(w, d) >= std::cos(b) ? L : 0.0f); }, n0, 512);
  const float s2 = std::sin(b) * std::sin(b);
  EXPECT_NEAR(sh.l0.x, L * s2 * std::cos(theta), 0.01f * L * s2);
  EXPECT_NEAR(sh.l1[0].x, L * s2 * std::sin(theta), 0.01f * L * s2);
  EXPECT_NEAR(sh.l1[1].x, 0.0f, 0.01f * L * s2);
  EXPECT_NEAR(sh.l1[2].x, 0.0f, 1e-6f);  // tangential by construction
}

// Light from one direction at theta = 30 degrees from n0, all of it direct (s = 1): the
// decode is the cosine law at every shading normal, in the plane of the light and out of it,
// 0 once the light is behind n (float rounding only).
TEST(ShProjection, DistantLightFollowsTheCosineLaw) {
  const vec3 n0(0.0f, 1.0f, 0.0f);
  const float theta = glm::radians(30.0f), e_over_pi = 2.0f;
  const vec3 w(std::sin(theta), std::cos(theta), 0.0f);
  ShL1 sh;
  sh.l0 = vec3(e_over_pi * std::cos(theta));
  sh.l1 = l1_of_sample(sh.l0, w, n0);
  sh.share = 1.0f;
  EXPECT_NEAR(sh.l1[0].x, e_over_pi * std::sin(theta), 1e-5f);
  EXPECT_NEAR(sh.l1[1].x, 0.0f, 1e-6f);
  for (float a_deg : {-80.0f, -45.0f, -20.0f, 0.0f, 10.0f, 25.0f, 45.0f, 70.0f})
    for (float b_deg : {0.0f, 30.0f}) {  // tilt a in the light's plane, b out of it
      const float a = glm::radians(a_deg), b = glm::radians(b_deg);
      const vec3 n(std::sin(a) * std::cos(b), std::cos(a) * std::cos(b), std::sin(b));
      const float truth = e_over_pi * std::max(0.0f, glm::dot(w, n));
      EXPECT_NEAR(decode_directional(sh, n, n0).x, truth, 1e-5f * e_over_pi)
          << a_deg << " " << b_deg;
    }
  // Light from behind the surface is no light.
  EXPECT_EQ(glm::length(l1_of_sample(vec3(1.0f), -w, n0)[0]), 0.0f);
}

// E/pi at normal n under a radiance field over the hemisphere above n0 (nothing below the
// plane, as the reference takes a bumped normal), by midpoint quadrature on a fine grid: an
// independent check of the decode.
float irradiance_over_pi(const std::function<float(vec3)>& radiance, vec3 n, vec3 n0) {
  const Frame frame(n0);
  const int side = 400;
  double sum = 0.0;
  for (int j = 0; j < side; ++j)
    for (int i = 0; i < side; ++i) {
      const vec2 u((float(i) + 0.5f) / float(side), (float(j) + 0.5f) / float(side));
      const vec3 w = frame.to_world(square_to_uniform_hemisphere(u));
      sum += 2.0 * double(radiance(w)) * std::max(0.0f, glm::dot(w, n));  // pdf 1 / (2 pi)
    }
  return float(sum / (double(side) * double(side)));
}

// A uniform sky of radiance L (the projection of the bake's estimator, no direct share):
// L1 = 0 and the decode at a normal tilted by a is L (1 + cos a) / 2, what the tilted normal
// sees of the sky (within 0.5% of the quadrature, its own error).
TEST(ShProjection, UniformSkyAtATiltedNormal) {
  const vec3 n0 = glm::normalize(vec3(0.2f, 1.0f, 0.1f));
  const float L = 3.0f;
  const ShL1 sh = project_radiance([&](vec3) { return vec3(L); }, n0, 64);
  const Frame frame(n0);
  for (float a_deg : {0.0f, 15.0f, 30.0f, 45.0f, 60.0f}) {
    const float a = glm::radians(a_deg);
    const vec3 n = frame.to_world(vec3(std::sin(a), 0.0f, std::cos(a)));
    const float truth = irradiance_over_pi([&](vec3) { return L; }, n, n0);
    EXPECT_NEAR(truth, L * (1.0f + std::cos(a)) / 2.0f, 5e-3f * L) << a_deg;
    EXPECT_NEAR(decode_directional(sh, n, n0).x, truth, 5e-3f * L) << a_deg;
  }
}

// Their sum, a sun of E/pi = 2 at 35 degrees (direct) over a uniform sky of L = 1: s is the
// sun's share of L0, and the decode is the sum's irradiance wherever the sun is in front of n.
TEST(ShProjection, SunAndSky) {
  const vec3 n0(0.0f, 0.0f, 1.0f);
  const float theta = glm::radians(35.0f), sun = 2.0f, L = 1.0f;
  const vec3 w(std::sin(theta), 0.0f, std::cos(theta));
  ShL1 sh = project_radiance([&](vec3) { return vec3(L); }, n0, 64);
  const vec3 sun_l0(sun * std::cos(theta));
  const std::array<vec3, 3> sun_l1 = l1_of_sample(sun_l0, w, n0);
  for (size_t a = 0; a < 3; ++a) sh.l1[a] += sun_l1[a];
  sh.share = sun_l0.x / (sun_l0.x + sh.l0.x);
  sh.l0 += sun_l0;
  for (float a_deg : {-40.0f, -10.0f, 20.0f, 50.0f}) {
    const float a = glm::radians(a_deg);
    const vec3 n(std::sin(a), 0.0f, std::cos(a));
    const float truth = sun * glm::dot(w, n) + L * (1.0f + std::cos(a)) / 2.0f;
    EXPECT_NEAR(decode_directional(sh, n, n0).x, truth, 5e-3f * truth) << a_deg;
  }
}

// De-ringing: after it, L0 + L1 . n >= 0 for every direction (before the clamp), and a band
// already within the bound is left alone.
TEST(ShProjection, DeringingKeepsEveryDirectionNonNegative) {
  Rng rng(7);
  for (int t = 0; t < 200; ++t) {
    ShL1 sh;
    sh.l0 = vec3(rng.next_float(), rng.next_float(), rng.next_float()) * 2.0f;
    for (vec3& axis : sh.l1)
      axis = (vec3(rng.next_float(), rng.next_float(), rng.next_float()) - 0.5f) * 8.0f;
    dering(sh);
    for (int k = 0; k < 400; ++k) {
      const vec2 u = rng.next_2d();
      const float z = 2.0f * u.x - 1.0f, r = std::sqrt(std::max(0.0f, 1.0f - z * z));
      const vec3 n(r * std::cos(2.0f * kPi * u.y), r * std::sin(2.0f * kPi * u.y), z);
      const vec3 raw = sh.l0 + sh.l1[0] * n.x + sh.l1[1] * n.y + sh.l1[2] * n.z;
      for (int c = 0; c < 3; ++c) ASSERT_GE(raw[c], -1e-5f * sh.l0[c]);
    }
  }
  ShL1 small;
  small.l0 = vec3(1.0f);
  small.l1 = {vec3(0.3f), vec3(-0.4f), vec3(0.5f)};
  const ShL1 kept = small;
  dering(small);
  for (size_t a = 0; a < 3; ++a) EXPECT_EQ(small.l1[a], kept.l1[a]);
}

// The ratio encoding: 0 exact, +-1 at the ends, 1/254 of L0 steps.
TEST(ShProjection, RatioEncoding) {
  const std::vector<vec3> l0 = {vec3(2.0f), vec3(1.0f, 0.0f, 4.0f)};
  const std::vector<vec3> l1 = {vec3(0.0f, 2.0f, -2.0f), vec3(0.37f, 0.5f, -1.3f)};
  const std::vector<uint8_t> bytes = encode_l1_ratios(l0, l1);
  EXPECT_EQ(decode_l1_ratio(&bytes[0], l0[0]), vec3(0.0f, 2.0f, -2.0f));
  const vec3 back = decode_l1_ratio(&bytes[3], l0[1]);
  EXPECT_NEAR(back.x, 0.37f, 0.5f / 127.0f);
  EXPECT_EQ(back.y, 0.0f);  // no L0: no L1
  EXPECT_NEAR(back.z, -1.3f, 4.0f * 0.5f / 127.0f);
}

// Lambert's vector irradiance of a uniform polygon of radiance L seen from p (wholly above
// every plane used): V = (L/2) sum_i angle_i * unit(v_i x v_{i+1}), E(n) = |n . V| (the sign
// follows the polygon's winding as seen from p).
glm::dvec3 vector_irradiance(const std::vector<glm::dvec3>& polygon, glm::dvec3 p, double L) {
  glm::dvec3 sum(0.0);
  for (size_t i = 0; i < polygon.size(); ++i) {
    const glm::dvec3 a = glm::normalize(polygon[i] - p);
    const glm::dvec3 b = glm::normalize(polygon[(i + 1) % polygon.size()] - p);
    const double angle = std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0));
    sum += angle * glm::normalize(glm::cross(a, b));
  }
  return 0.5 * L * sum;
}

// A 2 x 2 m floor under a small square light 1 m up, offset 0.5 m in x: nothing bounces (the
// light is black, nothing else is there), so the map is the direct term alone.
struct LitFloor {
  Scene scene;
  std::vector<glm::dvec3> light;
  float radiance = 40.0f;
};

LitFloor make_lit_floor() {
  LitFloor out;
  Material white;
  white.reflectance = vec3(0.5f);
  const int floor = test::add_material(out.scene, white);
  Material lamp;
  lamp.reflectance = vec3(0.0f);
  lamp.emission = vec3(out.radiance);
  const int light = test::add_material(out.scene, lamp);
  Mesh floor_mesh = test::make_quad(vec3(-1, 0, 1), vec3(2, 0, 0), vec3(0, 0, -2), floor, "floor");
  floor_mesh.bake.texel_size = 0.05f;
  out.scene.meshes.push_back(floor_mesh);
  // Facing down: corners so that cross(edge_u, edge_v) = -y.
  const vec3 corner(0.4f, 1.0f, -0.1f), eu(0.2f, 0, 0), ev(0, 0, 0.2f);
  out.scene.meshes.push_back(test::make_quad(corner, eu, ev, light, "light"));
  for (const vec3& v : {corner, corner + eu, corner + eu + ev, corner + ev})
    out.light.push_back(glm::dvec3(v));
  return out;
}

BakeResult directional_bake(const Scene& scene) {
  BakeParams params;
  params.illumination.rays_per_zone_side = 8;
  params.radiosity.ray_budget = 20'000;
  params.soft_texels.gather_rays = 0;
  return bake_scene(scene, params);
}

// The world position under node (i, j) of mesh m's chart, if the node's texel centre lies
// inside one of its triangles with a margin of `margin` texels; false otherwise.
bool node_position(const Mesh& mesh, int width, int height, int i, int j, float margin,
                   vec3& out) {
  const vec2 uv((float(i) + 0.5f) / float(width), (float(j) + 0.5f) / float(height));
  for (const uvec3& t : mesh.triangles) {
    const vec2 a = mesh.lightmap_uvs[t.x], b = mesh.lightmap_uvs[t.y], c = mesh.lightmap_uvs[t.z];
    const float det = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
    if (std::abs(det) < 1e-12f) continue;
    const float b1 = ((uv.x - a.x) * (c.y - a.y) - (c.x - a.x) * (uv.y - a.y)) / det;
    const float b2 = ((b.x - a.x) * (uv.y - a.y) - (uv.x - a.x) * (b.y - a.y)) / det;
    if (b1 < 0 || b2 < 0 || b1 + b2 > 1) continue;
    // Margin: the node's 2 x 2 texel footprint stays on the chart (a quad's chart is a
    // rectangle; nodes within `margin` texels of its uv bounds are skipped).
    vec2 lo(1e9f), hi(-1e9f);
    for (const vec2& p : mesh.lightmap_uvs) lo = glm::min(lo, p), hi = glm::max(hi, p);
    const vec2 m = margin / vec2(float(width), float(height));
    if (glm::any(glm::lessThan(uv, lo + m)) || glm::any(glm::greaterThan(uv, hi - m)))
      return false;
    out = (1 - b1 - b2) * mesh.positions[t.x] + b1 * mesh.positions[t.y] +
          b2 * mesh.positions[t.z];
    return true;
  }
  return false;
}

// On a real bake: the L0 band is the plain map bit for bit, and the direct term's L1 at each
// interior texel is Lambert's tangential vector irradiance over pi, de-ringed (the light is
// 0-62 degrees from the floor's normal across the floor: beyond 45, |L1| = L0).
TEST(DirectionalLightmap, DirectTermAgainstLambertAndPlainMapBits) {
  const LitFloor floor = make_lit_floor();
  const BakeResult bake = directional_bake(floor.scene);
  LightmapParams params;
  params.contents = LightmapContents::all;
  params.seed = 3;
  const Lightmap plain = bake_lightmap(floor.scene, bake, params);
  DirectionalMaps band;
  DirectionalParams directional;
  directional.gather_rays = 4;
  const Lightmap lightmap =
      bake_directional_lightmap(floor.scene, bake, params, directional, band);
  ASSERT_GT(lightmap.width, 0);
  EXPECT_TRUE(test::same_bits(lightmap.radiance, plain.radiance));
  EXPECT_TRUE(test::same_bits(lightmap.direct, plain.direct));
  EXPECT_EQ(lightmap.shadow_rays, plain.shadow_rays);

  const Mesh mesh = mesh_with_lightmap(floor.scene.meshes[0], bake.illumination, 0);
  int checked = 0;
  double l0_error = 0, l1_error = 0, l1_size = 0;
  for (int j = 0; j < lightmap.height; ++j)
    for (int i = 0; i < lightmap.width; ++i) {
      vec3 p;
      if (!node_position(mesh, lightmap.width, lightmap.height, i, j, 1.5f, p)) continue;
      const size_t k = size_t(j) * size_t(lightmap.width) + size_t(i);
      glm::dvec3 v = vector_irradiance(floor.light, glm::dvec3(p), floor.radiance) / glm::pi<double>();
      if (v.y < 0.0) v = -v;  // the winding's sign: the light is above the floor
      const double l0 = v.y;  // n0 = +y
      glm::dvec3 l1(v.x, 0.0, v.z);
      if (glm::length(l1) > l0) l1 *= l0 / glm::length(l1);  // de-ringed: |L1| <= L0
      // Footprint means of a smooth field and 64 shadow rays a node: a few percent.
      l0_error += std::abs(double(lightmap.radiance[k].x) - l0) / l0;
      const glm::dvec3 got(band.l1[0][k].x, band.l1[1][k].x, band.l1[2][k].x);
      l1_error += glm::length(got - l1) / l0;
      l1_size += glm::length(l1) / l0;
      // Nothing bounces: all of L0 is the direct term's.
      EXPECT_NEAR(band.share[k], 1.0f, 1e-4f);
      ++checked;
    }
  ASSERT_GT(checked, 400);
  EXPECT_LT(l0_error / checked, 0.02) << "mean relative error of L0";
  EXPECT_LT(l1_error / checked, 0.03) << "mean |L1 - Lambert| / L0 (mean |L1| / L0 "
                                       << l1_size / checked << ")";
  EXPECT_GT(l1_size / checked, 0.4);  // the test sees real directionality
}

// A 1 x 1 m white panel 1 m over a black 2 x 2 m floor, facing it, lit from below by a sun 60
// degrees from the vertical that reaches the panel only (the floor is lit from behind and
// shades none of the panel, which the black floor lights not at all): the panel's radiance is
// uniform, L = R E0 cos(60) / pi, and all of the floor's soft light comes from it, so the
// floor's soft band is Lambert's vector irradiance V of the panel: L0 = n0 . V / pi and
// L1 = P V / pi (bake/sh_projection.h). The floor has a flat normal map (n = n0): the bake
// gathers the band on bump- and normal-mapped surfaces only.
struct PanelOverFloor {
  Scene scene;
  std::vector<glm::dvec3> panel;
  float radiance = 0.0f;
};

PanelOverFloor make_panel_over_floor() {
  PanelOverFloor out;
  Material black;
  black.reflectance = vec3(0.0f);
  Material white;
  white.reflectance = vec3(0.8f);
  const int dark = test::add_material(out.scene, black), lit = test::add_material(out.scene, white);
  test::add_flat_normal_map(out.scene, dark);  // the floor takes a band: bake --directional
  Mesh floor = test::make_quad(vec3(0, -1, 0), vec3(2, 0, 0), vec3(0, 2, 0), dark, "floor");
  floor.bake.texel_size = 0.05f;
  out.scene.meshes.push_back(floor);
  const vec3 corner(0.5f, -0.5f, 1.0f), eu(0, 1, 0), ev(1, 0, 0);  // facing -z
  out.scene.meshes.push_back(test::make_quad(corner, eu, ev, lit, "panel"));
  for (const vec3& v : {corner, corner + eu, corner + eu + ev, corner + ev})
    out.panel.push_back(glm::dvec3(v));
  Lamp sun;
  sun.kind = LampKind::directional;
  const float theta = glm::radians(60.0f), e0 = 2.0f;
  sun.direction = vec3(std::sin(theta), 0.0f, std::cos(theta));  // travelling up
  sun.intensity = vec3(e0);
  out.scene.lights.push_back(sun);
  out.radiance = 0.8f * e0 * std::cos(theta) / kPi;
  return out;
}

BakeParams soft_band_params() {
  BakeParams params;
  params.illumination.rays_per_zone_side = 8;
  params.radiosity.ray_budget = 400'000;
  params.soft_texels.points_side = 2;
  params.soft_texels.gather_rays = 32;
  params.illumination.directional = true;
  params.soft_band.gather_rays = 64;
  return params;
}

// The bake's soft band on the floor against Lambert's closed form (de-ringing does not act:
// the panel is within 45 degrees of every node checked), and the decode with s = 0.
TEST(SoftBand, PanelOverADarkFloorAgainstLambert) {
  const PanelOverFloor scene = make_panel_over_floor();
  const BakeResult bake = bake_scene(scene.scene, soft_band_params());
  const IlluminationMaps& maps = bake.illumination;
  const SoftTexelMap& soft = bake.soft_texels;
  for (const std::vector<vec3>& axis : soft.l1) ASSERT_EQ(axis.size(), soft.radiance.size());
  const Mesh mesh = mesh_with_lightmap(scene.scene.meshes[0], maps, 0);
  int checked = 0;
  double l0_error = 0, l1_error = 0, l1_size = 0, decode_error = 0;
  for (int j = 0; j < maps.height; ++j)
    for (int i = 0; i < maps.width; ++i) {
      vec3 p;
      if (!node_position(mesh, maps.width, maps.height, i, j, 1.5f, p)) continue;
      if (std::abs(p.x - 1.0f) > 0.4f || std::abs(p.y) > 0.4f) continue;  // under the panel
      const size_t k = size_t(j) * size_t(maps.width) + size_t(i);
      glm::dvec3 v = vector_irradiance(scene.panel, glm::dvec3(p), scene.radiance) /
                     glm::pi<double>();
      if (v.z < 0.0) v = -v;  // the winding's sign: the panel is above the floor
      const double l0 = v.z;  // n0 = +z
      const glm::dvec3 l1(v.x, v.y, 0.0);
      ASSERT_LT(glm::length(l1), 0.9 * l0);  // no de-ringing here
      l0_error += std::abs(double(soft.radiance[k].x) - l0) / l0;
      const glm::dvec3 got(soft.l1[0][k].x, soft.l1[1][k].x, soft.l1[2][k].x);
      l1_error += glm::length(got - l1) / l0;
      l1_size += glm::length(l1) / l0;
      // At a normal tilted 30 degrees toward the panel's centre or away from it, the decode
      // (s = 0) is the band's: L0 (1 + n . n0) / 2 + L1 . n.
      const vec3 n0(0, 0, 1);
      for (float tilt : {-30.0f, 30.0f}) {
        const float a = glm::radians(tilt);
        const vec3 n(std::sin(a), 0.0f, std::cos(a));  // n0 turned about y
        ShL1 sh{soft.radiance[k], {soft.l1[0][k], soft.l1[1][k], soft.l1[2][k]}, 0.0f};
        const double expected = l0 * (1.0 + double(n.z)) / 2.0 + glm::dot(l1, glm::dvec3(n));
        decode_error += std::abs(double(decode_directional(sh, n, n0).x) - expected) / l0 / 2.0;
      }
      ++checked;
    }
  std::printf("soft band under the panel: %d nodes, mean |L0 - Lambert| %.4f, |L1 - Lambert| "
              "%.4f of L0 (mean |L1| %.3f of L0), decode at 30 degrees %.4f\n",
              checked, l0_error / checked, l1_error / checked, l1_size / checked,
              decode_error / checked);
  ASSERT_GT(checked, 100);
  // Measured: L0 2.1%, L1 1.5%, the decode 2.1% (the soft map's and the gather's noise; the
  // soft map at 20k radiosity rays and 8 gather rays was 13% off).
  EXPECT_LT(l0_error / checked, 0.03) << "the soft map's L0 (the gather's mean)";
  EXPECT_LT(l1_error / checked, 0.03) << "64 rays a point, a 7 x 7 box: the gather's noise";
  EXPECT_LT(decode_error / checked, 0.03);
  EXPECT_GT(l1_size / checked, 0.2);  // the test sees real directionality
}

// The setting adds the band and leaves every other term's bits; the band has the same bits
// at 1 and 2 threads; a scene without bump or normal maps gets none.
TEST(SoftBand, KeepsTheMapsBitsAndTheThreadCounts) {
  const PanelOverFloor scene = make_panel_over_floor();
  BakeParams params = soft_band_params();
  params.soft_band.gather_rays = 4;
  const auto bake_at = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
    return bake_scene(scene.scene, params);
  };
  const BakeResult one = bake_at(1), two = bake_at(2);
  for (size_t a = 0; a < 3; ++a) {
    ASSERT_EQ(one.soft_texels.l1[a].size(), one.soft_texels.radiance.size());
    EXPECT_TRUE(test::same_bits(one.soft_texels.l1[a], two.soft_texels.l1[a])) << "axis " << a;
  }
  params.illumination.directional = false;
  const BakeResult plain = bake_scene(scene.scene, params);
  EXPECT_TRUE(plain.soft_texels.l1[0].empty());
  EXPECT_TRUE(test::same_bits(plain.soft_texels.radiance, two.soft_texels.radiance));
  EXPECT_TRUE(test::same_bits(plain.illumination.radiance, two.illumination.radiance));
  // Without a bump- or normal-mapped surface no decode would differ from the map: no band.
  Scene flat = scene.scene;
  for (Material& m : flat.materials) m.bump = BumpKind::none;
  params.illumination.directional = true;
  const BakeResult unbumped = bake_scene(flat, params);
  EXPECT_TRUE(unbumped.soft_texels.l1[0].empty());
  EXPECT_EQ(unbumped.soft_texels.band_rays, 0u);
}

// The export takes the bake's soft band (no second gather) where the bake has one: the same
// gather at the same seed and defaults, so on bump- and normal-mapped surfaces (here every
// one) its L1 is the gathering export's wherever the bake's de-ringing against the soft map
// alone did not act.
TEST(SoftBand, TheExportTakesTheBakesBandAsItsOwnGather) {
  PanelOverFloor scene = make_panel_over_floor();
  test::add_flat_normal_map(scene.scene, 1);  // the panel too: the bake's band covers both
  BakeParams bake_params = soft_band_params();
  bake_params.soft_band = DirectionalParams{};  // the export's defaults
  const BakeResult bake = bake_scene(scene.scene, bake_params);
  BakeResult without = bake;
  for (std::vector<vec3>& axis : without.soft_texels.l1) axis.clear();
  LightmapParams params;
  params.seed = bake.seed;
  DirectionalMaps taken, gathered;
  const Lightmap map = bake_directional_lightmap(scene.scene, bake, params, {}, taken);
  bake_directional_lightmap(scene.scene, without, params, {}, gathered);
  EXPECT_EQ(taken.gather_rays, 0u);
  EXPECT_GT(gathered.gather_rays, 0u);
  const SoftTexelMap& soft = bake.soft_texels;
  const IlluminationMaps& maps = bake.illumination;
  int compared = 0;
  double worst = 0.0, band = 0.0;
  for (size_t k = 0; k < soft.radiance.size(); ++k) {
    if (!maps.valid[k] || !(map.radiance[k].x > 0.0f)) continue;
    const vec3 l1(soft.l1[0][k].x, soft.l1[1][k].x, soft.l1[2][k].x);
    if (glm::length(l1) > 0.99f * soft.radiance[k].x) continue;  // the bake's de-ringing acted
    for (size_t a = 0; a < 3; ++a) {
      worst = std::max(worst, double(std::abs(taken.l1[a][k].x - gathered.l1[a][k].x)) /
                                  double(map.radiance[k].x));
      band += std::abs(double(gathered.l1[a][k].x) / double(map.radiance[k].x));
    }
    ++compared;
  }
  std::printf("export with the bake's soft band: %d texels, worst difference %.2e of L0 "
              "(mean |L1| %.3f of L0)\n", compared, worst, band / std::max(compared, 1));
  ASSERT_GT(compared, 400);
  EXPECT_LT(worst, 1e-4);
  EXPECT_GT(band / compared, 0.1);
}

// A bake with the `directional` setting brings its caustic band to the export: on the ceiling
// lit by the sun through a plane mirror (sun_over_mirror.h; no direct light, a little soft
// light), the export's L1 is the bake's caustic L1 where the caustic lies (the soft term's own
// gather off), and its share s is the caustic's part of L0; a bake without the band gives
// the export no L1 at all.
TEST(DirectionalLightmap, TheBakesCausticBandGoesIntoTheExport) {
  const test::SunOverMirror s;
  BakeParams bake_params;
  bake_params.illumination.rays_per_zone_side = 64;
  bake_params.radiosity.ray_budget = 20'000;
  bake_params.soft_texels.gather_rays = 0;
  bake_params.illumination.directional = true;
  const BakeResult bake = bake_scene(s.scene, bake_params);
  bake_params.illumination.directional = false;
  const BakeResult plain = bake_scene(s.scene, bake_params);
  const IlluminationMaps& caustic = bake.illumination;
  ASSERT_EQ(caustic.l1[0].size(), caustic.radiance.size());
  LightmapParams params;
  DirectionalParams directional;
  directional.gather_rays = 0;
  DirectionalMaps band, plain_band;
  const Lightmap lightmap = bake_directional_lightmap(s.scene, bake, params, directional, band);
  bake_directional_lightmap(s.scene, plain, params, directional, plain_band);
  ASSERT_EQ(lightmap.width, caustic.width);
  float peak = 0.0f;
  for (const vec3& v : caustic.radiance) peak = std::max(peak, v.x);
  int checked = 0;
  double worst = 0.0, worst_plain = 0.0, worst_share = 0.0;
  for (size_t k = 0; k < caustic.radiance.size(); ++k) {
    if (!caustic.valid[k] || !(caustic.radiance[k].x > 0.5f * peak)) continue;
    const float l0 = lightmap.radiance[k].x;
    for (size_t a = 0; a < 3; ++a) {
      worst = std::max(worst, double(std::abs(band.l1[a][k].x - caustic.l1[a][k].x) / l0));
      worst_plain = std::max(worst_plain, double(std::abs(plain_band.l1[a][k].x) / l0));
    }
    const double share = luminance(caustic.radiance[k]) / luminance(lightmap.radiance[k]);
    worst_share = std::max(worst_share, std::abs(double(band.share[k]) - share));
    ++checked;
  }
  std::printf("export of a caustic band: %d texels, worst |L1 - caustic L1| %.2e of L0, "
              "without the band %.2e, share %.2e\n",
              checked, worst, worst_plain, worst_share);
  ASSERT_GT(checked, 50);
  EXPECT_LT(worst, 1e-4);
  EXPECT_LT(worst_plain, 1e-6);
  EXPECT_LT(worst_share, 1e-3);
}

// A .glb's images as their PNG headers give them (size, bits, channels from the colour type;
// no texels): tinygltf's own loader widens every image to RGBA.
tinygltf::Model load_png_headers(const std::string& path) {
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(
      [](tinygltf::Image* image, int, std::string* err, std::string*, int, int,
         const unsigned char* bytes, int size, void*) {
        if (size < 26 || std::memcmp(bytes + 12, "IHDR", 4) != 0) {
          *err = "not a PNG";
          return false;
        }
        const auto be32 = [&](int at) {
          return int(uint32_t(bytes[at]) << 24 | uint32_t(bytes[at + 1]) << 16 |
                     uint32_t(bytes[at + 2]) << 8 | uint32_t(bytes[at + 3]));
        };
        image->width = be32(16);
        image->height = be32(20);
        image->bits = bytes[24];
        const int colour_type = bytes[25];  // 0 grey, 2 RGB, 4 grey + alpha, 6 RGBA
        image->component = colour_type == 6 ? 4 : colour_type == 2 ? 3 : colour_type == 4 ? 2 : 1;
        return true;
      },
      nullptr);
  tinygltf::Model model;
  std::string err, warn;
  EXPECT_TRUE(loader.LoadBinaryFromFile(&model, &err, &warn, path)) << err;
  return model;
}

// The bytes of an image's texels, 8 bits a channel.
size_t texel_bytes(const tinygltf::Image& image) {
  return size_t(image.width) * size_t(image.height) * size_t(image.component);
}

const tinygltf::Image& image_of(const tinygltf::Model& model, const tinygltf::Value& binding) {
  const int texture = binding.Get("index").GetNumberAsInt();
  return model.images.at(size_t(model.textures.at(size_t(texture)).source));
}

// The first material with the directional extension: the extension, the L1 images (x, y, z)
// and the plain map's (MOZ_lightmap's).
const tinygltf::Value* directional_extension(const tinygltf::Model& model,
                                             std::vector<const tinygltf::Image*>& l1,
                                             const tinygltf::Image*& plain) {
  for (const tinygltf::Material& material : model.materials) {
    const auto found = material.extensions.find(kDirectionalExtension);
    if (found == material.extensions.end()) continue;
    for (int a = 0; a < 3; ++a) l1.push_back(&image_of(model, found->second.Get("l1").Get(a)));
    plain = &image_of(model, material.extensions.at("MOZ_lightmap"));
    return &found->second;
  }
  return nullptr;
}

// Export and read back: the extension names three textures and the decoded L1 is the band
// within the 8-bit step (1/127 of L0), for every texel. The default file holds three RGB
// maps, exactly 3x the plain map's bytes (4x with it), and no share (s = 0 on reading); with
// `directional_share` the x map is RGBA and reads back s.
TEST(DirectionalLightmap, GltfExtensionRoundTrip) {
  const LitFloor floor = make_lit_floor();
  const BakeResult bake = directional_bake(floor.scene);
  const std::string dir = test::fresh_dir("lightmap", "directional_roundtrip");
  LightmapParams params;
  params.contents = LightmapContents::all;
  params.seed = bake.seed;
  GltfExportOptions options;
  options.contents = LightmapContents::all;
  options.directional = true;
  options.directional_params.gather_rays = 4;
  DirectionalMaps band;
  const Lightmap lightmap =
      bake_directional_lightmap(floor.scene, bake, params, options.directional_params, band);
  double worst_share = 0.0;  // of the band itself: the test sees a real share
  for (float s : band.share) worst_share = std::max(worst_share, double(s));
  EXPECT_GT(worst_share, 0.5);
  for (const bool share : {false, true}) {
    const std::string path = dir + (share ? "/share.glb" : "/floor.glb");
    options.directional_share = share;
    const GltfExportInfo info = export_gltf(path, floor.scene, bake, options);
    EXPECT_TRUE(info.directional);
    const tinygltf::Model model = load_png_headers(path);
    std::vector<const tinygltf::Image*> images;
    const tinygltf::Image* map = nullptr;
    const tinygltf::Value* extension = directional_extension(model, images, map);
    ASSERT_NE(extension, nullptr);
    ASSERT_TRUE(extension->Get("share").IsBool());
    EXPECT_EQ(extension->Get("share").Get<bool>(), share);
    const tinygltf::Image& plain = *map;
    EXPECT_EQ(plain.component, 3);  // the sRGB map
    const size_t plain_bytes = texel_bytes(plain);
    EXPECT_EQ(plain_bytes, size_t(lightmap.width) * size_t(lightmap.height) * 3u);
    size_t band_bytes = 0;
    for (size_t a = 0; a < 3; ++a) {
      EXPECT_EQ(images[a]->component, share && a == 0 ? 4 : 3) << a;
      EXPECT_EQ(images[a]->bits, 8);
      EXPECT_EQ(images[a]->width, plain.width);
      EXPECT_EQ(images[a]->height, plain.height);
      band_bytes += texel_bytes(*images[a]);
    }
    EXPECT_EQ(band_bytes, share ? plain_bytes * 3 + plain_bytes / 3 : plain_bytes * 3);

    const Scene scene = load_scene(path).scene;
    const BakeResult back = read_gltf_bake(path, scene);
    const IlluminationMaps& maps = back.illumination;
    ASSERT_EQ(maps.width, lightmap.width);
    for (size_t a = 0; a < 3; ++a) ASSERT_EQ(maps.l1[a].size(), lightmap.radiance.size());
    double worst = 0.0;
    for (size_t k = 0; k < lightmap.radiance.size(); ++k)
      for (size_t a = 0; a < 3; ++a)
        for (int c = 0; c < 3; ++c) {
          const double l0 = std::max(1e-6f, lightmap.radiance[k][c]);
          // The reader decodes against the EXR's half-float L0: its rounding too.
          worst = std::max(worst, std::abs(double(maps.l1[a][k][c]) - band.l1[a][k][c]) / l0);
        }
    EXPECT_LT(worst, 0.5 / 127.0 + 2e-3);
    ASSERT_EQ(maps.l1_share.size(), band.share.size());
    for (size_t k = 0; k < band.share.size(); ++k)
      ASSERT_NEAR(maps.l1_share[k], share ? band.share[k] : 0.0f, 0.5f / 255.0f + 1e-6f) << k;
  }
  // A plain export has no band.
  const std::string plain = dir + "/plain.glb";
  options.directional = false;
  export_gltf(plain, floor.scene, bake, options);
  const BakeResult plain_back = read_gltf_bake(plain, load_scene(plain).scene);
  EXPECT_TRUE(plain_back.illumination.l1[0].empty());
}

// Export: a height bump becomes the normal map that shades the same (height_to_normal.h). On
// a 2 x 3 m wall (UVs 2 and 3 m per unit) with a bumpy height texture, the normal map's
// normal (bake/bump.h's normal-map path, MikkTSpace tangents as the loaders make them) is the
// height bump's at every texel centre, to the 8-bit PNG's rounding (the test reads floats:
// closer than 0.01 rad).
TEST(HeightToNormal, ShadesAsTheHeightBump) {
  Scene scene;
  Material material;
  material.bump = BumpKind::height;
  material.bump_scale = 0.01f;
  material.bump_texture = 0;
  const int index = test::add_material(scene, material);
  Mesh wall = test::make_quad(vec3(0, 0, 0), vec3(2, 0, 0), vec3(0, 3, 0), index, "wall");
  generate_mikktspace_tangents(wall);
  scene.meshes.push_back(wall);
  Texture height;
  height.width = 64;
  height.height = 48;
  height.channels = 1;
  for (int j = 0; j < height.height; ++j)
    for (int i = 0; i < height.width; ++i)
      height.texels.push_back(0.5f + 0.3f * std::sin(0.3f * float(i)) * std::cos(0.2f * float(j)) +
                              0.1f * float(j % 5));
  scene.textures.push_back(height);
  const UvFrame frame = uv_frame(scene, index);
  EXPECT_NEAR(frame.metres.x, 2.0f, 1e-5f);
  EXPECT_NEAR(frame.metres.y, 3.0f, 1e-5f);
  Scene mapped = scene;
  mapped.textures[0] = height_to_normal_map(height, material.bump_scale, frame);
  mapped.materials[size_t(index)].bump = BumpKind::normal_map;
  mapped.materials[size_t(index)].bump_scale = 1.0f;
  double worst = 0.0, tilt = 0.0;
  int count = 0;
  for (int j = 1; j < height.height - 1; ++j)
    for (int i = 1; i < height.width - 1; ++i) {
      SurfacePoint sp;
      sp.uv = vec2((float(i) + 0.5f) / float(height.width), (float(j) + 0.5f) / float(height.height));
      // The quad's triangle holding that uv (make_quad: corner 0 at uv (0, 0)).
      sp.triangle = sp.uv.x >= sp.uv.y ? 0u : 1u;
      sp.mesh = 0;
      sp.geometric_normal = sp.shading_normal = vec3(0, 0, 1);
      sp.position = vec3(2.0f * sp.uv.x, 3.0f * sp.uv.y, 0.0f);
      sp.tangent = wall.tangents[0];
      sp.material = &scene.materials[size_t(index)];
      const vec3 from_height = bumped_normal(scene, sp);
      sp.material = &mapped.materials[size_t(index)];
      const vec3 from_map = bumped_normal(mapped, sp);
      worst = std::max(worst, double(std::acos(std::min(1.0f, glm::dot(from_height, from_map)))));
      tilt += std::acos(std::min(1.0f, from_height.z));
      ++count;
    }
  EXPECT_LT(worst, 0.01) << "radians";
  EXPECT_GT(tilt / count, 0.015) << "the bumps tilt the normal (radians, mean)";
}

}  // namespace
}  // namespace lb
