// The viewer's lamps (point, spot, directional) against closed forms, on a white floor
// (reflectance rho, Lambertian) seen from above; the snapshot is linear radiance, the direct
// term R * E/pi (shaders/lamps.glsl).
//   point lamp of I W/sr at height h, floor point at horizontal offset x:
//     rho * I * h / (pi * (h^2 + x^2)^(3/2))   (rho I / (pi h^2) right below: cos^3 falloff)
//   spot: the same times lb::spot_falloff (1 inside the inner cone, 0 outside the outer)
//   directional lamp of E W/m^2 at angle theta from the normal: rho * E * cos(theta) / pi.
// Each pixel's floor point comes from the same camera ray the rasteriser samples
// (test::camera_ray) traced against the scene, so every pixel has its own exact value.
// Shadows: a 1.2 m box on the floor; a floor point whose segment to the lamp crosses the box
// shrunk by 20 cm must get no light, one whose segment misses the box grown by 10 cm all of it.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/gtc/constants.hpp>
#include <optional>

#include "bake/accel.h"
#include "bake/light_sources.h"
#include "bake/surface.h"
#include "test_helpers.h"
#include "viewer/offscreen_context.h"
#include "viewer/renderer.h"
#include "viewer/snapshot.h"
#include "viewer_test_scenes.h"

namespace lb {
namespace {

constexpr int kWidth = 160, kHeight = 120;
constexpr float kRho = 0.8f;
const float kPi = glm::pi<float>();
const vec3 kBoxMin{-0.6f, 0.0f, -0.6f}, kBoxMax{0.6f, 1.2f, 0.6f};

// A 16 x 16 m white floor at y = 0 facing up, optionally the box, one lamp, a camera above.
Scene lamp_floor(const Lamp& lamp, bool box, int floor_material_bump_texture = -1) {
  Scene scene;
  scene.source_path = "lamp floor (in code)";
  Material white;
  white.name = "white";
  white.reflectance = vec3(kRho);
  if (floor_material_bump_texture >= 0) {
    white.bump = BumpKind::normal_map;
    white.bump_texture = floor_material_bump_texture;
  }
  const int id = test::add_material(scene, white);
  // Front along cross(+z, +x) = +y.
  scene.meshes.push_back(test::make_quad({-8, 0, -8}, {0, 0, 16}, {16, 0, 0}, id, "floor"));
  if (box) {
    Material grey;
    grey.reflectance = vec3(0.5f);
    scene.meshes.push_back(
        test::make_box(kBoxMin, kBoxMax, test::add_material(scene, grey), false, "box"));
  }
  scene.lights.push_back(lamp);
  Camera camera;
  camera.position = {0.0f, 6.0f, 5.0f};
  camera.target = {0.3f, 0.0f, 0.0f};
  camera.vertical_fov_deg = 60.0f;
  scene.cameras.push_back(camera);
  return scene;
}

Image render_direct(const Scene& scene, int pixel_samples = 1) {
  SnapshotOptions options;
  options.width = kWidth;
  options.height = kHeight;
  options.settings.term = Term::direct;
  options.settings.shadows = true;
  options.pixel_samples = pixel_samples;
  return render_snapshot(scene, nullptr, options);
}

// The floor point each pixel sees; nullopt where it sees something else or nothing, and on
// silhouettes (a 4-neighbour sees something else), where the rasteriser and the ray may
// disagree by a hair on what the pixel centre hits.
std::vector<std::optional<vec3>> floor_points(const Scene& scene) {
  const Accel accel(scene);
  const ViewCamera view = choose_camera(scene, "");
  std::vector<std::optional<vec3>> hits(size_t(kWidth * kHeight));
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const Ray ray = test::camera_ray(view, kWidth, kHeight, x, y);
      const auto hit = accel.intersect(ray);
      if (hit && hit->mesh == 0) hits[size_t(y * kWidth + x)] = ray.origin + hit->t * ray.direction;
    }
  }
  auto floor_at = [&](int x, int y) {
    return x < 0 || y < 0 || x >= kWidth || y >= kHeight || hits[size_t(y * kWidth + x)];
  };
  std::vector<std::optional<vec3>> points(hits.size());
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      if (floor_at(x - 1, y) && floor_at(x + 1, y) && floor_at(x, y - 1) && floor_at(x, y + 1))
        points[size_t(y * kWidth + x)] = hits[size_t(y * kWidth + x)];
    }
  }
  return points;
}

// R * E/pi of `lamp` at floor point p (normal +y), unoccluded, from the closed forms above.
vec3 expected_radiance(const Lamp& lamp, vec3 p) {
  if (lamp.kind == LampKind::directional) {
    return kRho * lamp.intensity * std::max(0.0f, -lamp.direction.y) / kPi;
  }
  const vec3 to_lamp = lamp.position - p;
  const float h = to_lamp.y;
  const float d = glm::length(to_lamp);
  const float falloff = spot_falloff(lamp, glm::dot(-to_lamp / d, lamp.direction));
  return kRho * lamp.intensity * falloff * range_window(lamp, d) * h / (kPi * d * d * d);
}

// Whether the segment a -> b crosses the box [lo, hi] (slab test).
bool segment_hits_box(vec3 a, vec3 b, vec3 lo, vec3 hi) {
  float t0 = 0.0f, t1 = 1.0f;
  for (int k = 0; k < 3; ++k) {
    const float d = b[k] - a[k];
    if (std::abs(d) < 1e-12f) {
      if (a[k] < lo[k] || a[k] > hi[k]) return false;
      continue;
    }
    float ta = (lo[k] - a[k]) / d, tb = (hi[k] - a[k]) / d;
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  return true;
}

vec3 towards_lamp_end(const Lamp& lamp, vec3 p) {
  return lamp.kind == LampKind::directional ? p - 100.0f * lamp.direction : lamp.position;
}

struct Comparison {
  double worst = 0.0;  // largest |gl - expected| / expected over the compared pixels, any channel
  int pixels = 0;
};

// Relative errors over floor pixels where `use(p, expected)` holds.
template <class Use>
Comparison compare(const Image& image, const std::vector<std::optional<vec3>>& points,
                   const Lamp& lamp, Use use) {
  Comparison c;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const auto& p = points[size_t(y * kWidth + x)];
      if (!p) continue;
      const vec3 expected = expected_radiance(lamp, *p);
      if (!use(*p, expected)) continue;
      for (int k = 0; k < 3; ++k) {
        c.worst =
            std::max(c.worst, std::abs(double(image.at(x, y, k)) - expected[k]) / expected[k]);
      }
      ++c.pixels;
    }
  }
  return c;
}

// The floor pixel whose point lies nearest to `target` (horizontally).
std::pair<int, int> nearest_pixel(const std::vector<std::optional<vec3>>& points, vec3 target) {
  std::pair<int, int> best{-1, -1};
  float best_d = 1e30f;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const auto& p = points[size_t(y * kWidth + x)];
      if (!p) continue;
      const float d = glm::length(vec3(p->x - target.x, 0.0f, p->z - target.z));
      if (d < best_d) best_d = d, best = {x, y};
    }
  }
  return best;
}

double relative_error_at(const Image& image, const std::vector<std::optional<vec3>>& points,
                         const Lamp& lamp, std::pair<int, int> pixel) {
  const vec3 p = *points[size_t(pixel.second * kWidth + pixel.first)];
  const vec3 expected = expected_radiance(lamp, p);
  double worst = 0.0;
  for (int k = 0; k < 3; ++k) {
    worst = std::max(worst, std::abs(double(image.at(pixel.first, pixel.second, k)) - expected[k]) /
                                expected[k]);
  }
  return worst;
}

Lamp point_lamp(vec3 position, vec3 intensity) {
  Lamp lamp;
  lamp.name = "point";
  lamp.kind = LampKind::point;
  lamp.position = position;
  lamp.intensity = intensity;
  return lamp;
}

Lamp spot_lamp(vec3 position, vec3 direction, float inner_deg, float outer_deg, vec3 intensity) {
  Lamp lamp = point_lamp(position, intensity);
  lamp.name = "spot";
  lamp.kind = LampKind::spot;
  lamp.direction = glm::normalize(direction);
  lamp.inner_cone = glm::radians(inner_deg);
  lamp.outer_cone = glm::radians(outer_deg);
  return lamp;
}

Lamp directional_lamp(vec3 direction, vec3 irradiance) {
  Lamp lamp;
  lamp.name = "sun";
  lamp.kind = LampKind::directional;
  lamp.direction = glm::normalize(direction);
  lamp.intensity = irradiance;
  return lamp;
}

TEST(ViewerLamps, PointLampInverseSquareAndCosineCubed) {
  const float h = 2.0f;
  const Lamp lamp = point_lamp({0.0f, h, 0.0f}, {10.0f, 5.0f, 2.5f});
  const Scene scene = lamp_floor(lamp, false);
  const Image image = render_direct(scene);
  const auto points = floor_points(scene);
  const auto below = nearest_pixel(points, lamp.position);
  const double at_below = relative_error_at(image, points, lamp, below);
  // Out to 4 m (cos^3 = 0.088 there).
  const Comparison falloff = compare(image, points, lamp, [&](vec3 p, vec3) {
    return glm::length(vec3(p.x, 0.0f, p.z)) < 2.0f * h;
  });
  std::printf(
      "point: below the lamp (%.3g W/(sr m^2) expected) relative error %.2e; falloff "
      "worst %.2e over %d pixels\n",
      double(kRho * lamp.intensity.x / (kPi * h * h)), at_below, falloff.worst, falloff.pixels);
  EXPECT_LT(at_below, 0.01);
  EXPECT_GT(falloff.pixels, 3000);
  EXPECT_LT(falloff.worst, 0.02);
}

TEST(ViewerLamps, SpotLampInsideInnerConeAndDarkOutsideOuter) {
  const float h = 3.0f;
  const Lamp lamp = spot_lamp({0.0f, h, 0.0f}, {0.0f, -1.0f, 0.0f}, 30.0f, 40.0f, {8, 8, 4});
  const Scene scene = lamp_floor(lamp, false);
  const Image image = render_direct(scene);
  const auto points = floor_points(scene);
  auto angle_deg = [&](vec3 p) {
    return glm::degrees(std::atan2(glm::length(vec3(p.x, 0.0f, p.z)), h));
  };
  const double at_below =
      relative_error_at(image, points, lamp, nearest_pixel(points, lamp.position));
  const Comparison inner =
      compare(image, points, lamp, [&](vec3 p, vec3) { return angle_deg(p) < 29.5f; });
  // The ramp between the cones, where it is above 1% of the peak (lb::spot_falloff mirrored).
  const vec3 peak = expected_radiance(lamp, {0, 0, 0});
  const Comparison ramp = compare(image, points, lamp, [&](vec3 p, vec3 e) {
    return angle_deg(p) > 30.5f && e.x > 0.01f * peak.x;
  });
  double outside_max = 0.0;
  int outside = 0;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const auto& p = points[size_t(y * kWidth + x)];
      if (!p || angle_deg(*p) < 40.5f) continue;
      for (int k = 0; k < 3; ++k) outside_max = std::max(outside_max, double(image.at(x, y, k)));
      ++outside;
    }
  }
  std::printf(
      "spot: below %.2e, inner cone worst %.2e over %d pixels, ramp worst %.2e over %d, "
      "outside the outer cone max %.3g over %d pixels\n",
      at_below, inner.worst, inner.pixels, ramp.worst, ramp.pixels, outside_max, outside);
  EXPECT_LT(at_below, 0.01);
  EXPECT_GT(inner.pixels, 1000);
  EXPECT_LT(inner.worst, 0.02);
  EXPECT_GT(ramp.pixels, 300);
  EXPECT_LT(ramp.worst, 0.05);  // the ramp's steep tail magnifies float rounding of cos
  EXPECT_GT(outside, 5000);
  EXPECT_EQ(outside_max, 0.0);
}

// glTF's range window (lb::range_window) on top of the inverse square law, and nothing beyond
// the range.
TEST(ViewerLamps, PointLampRangeWindow) {
  Lamp lamp = point_lamp({0.0f, 2.0f, 0.0f}, {10.0f, 10.0f, 10.0f});
  lamp.range = 3.5f;
  const Scene scene = lamp_floor(lamp, false);
  const Image image = render_direct(scene);
  const auto points = floor_points(scene);
  const vec3 peak = expected_radiance(lamp, {0, 0, 0});
  // Where the window leaves more than 1% of the peak; its steep end magnifies rounding.
  const Comparison inside =
      compare(image, points, lamp, [&](vec3, vec3 e) { return e.x > 0.01f * peak.x; });
  double beyond_max = 0.0;
  int beyond = 0;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const auto& p = points[size_t(y * kWidth + x)];
      if (!p || glm::length(*p - lamp.position) < lamp.range) continue;
      beyond_max = std::max(beyond_max, double(image.at(x, y, 0)));
      ++beyond;
    }
  }
  std::printf("range: worst %.2e over %d pixels; beyond the range max %.3g over %d pixels\n",
              inside.worst, inside.pixels, beyond_max, beyond);
  EXPECT_GT(inside.pixels, 3000);
  EXPECT_LT(inside.worst, 0.02);
  EXPECT_GT(beyond, 3000);
  EXPECT_EQ(beyond_max, 0.0);
}

TEST(ViewerLamps, DirectionalLampEverywhereUnshadowed) {
  const float theta = glm::radians(35.0f);
  const Lamp lamp = directional_lamp({std::sin(theta), -std::cos(theta), 0.0f}, {3.0f, 2.0f, 1.0f});
  const Scene scene = lamp_floor(lamp, false);
  const Image image = render_direct(scene);
  const auto points = floor_points(scene);
  const Comparison all = compare(image, points, lamp, [](vec3, vec3) { return true; });
  std::printf("directional: rho E cos / pi = %.4g, worst relative error %.2e over %d pixels\n",
              double(expected_radiance(lamp, {}).x), all.worst, all.pixels);
  EXPECT_GT(all.pixels, 10000);
  EXPECT_LT(all.worst, 0.01);
}

// A tilted normal map (one texel, tangent-space normal at 40 degrees from the surface's) under
// a sun straight above: whatever way the tangent frame turns, cos = cos(40 deg).
TEST(ViewerLamps, NormalMapTiltsTheLampsCosine) {
  const float tilt = glm::radians(40.0f);
  Lamp lamp = directional_lamp({0.0f, -1.0f, 0.0f}, {2.0f, 2.0f, 2.0f});
  Scene scene = lamp_floor(lamp, false, 0);
  Texture normal_map;
  normal_map.path = "tilted normal (in code)";
  normal_map.width = normal_map.height = 1;
  normal_map.channels = 3;
  normal_map.texels = {0.5f + 0.5f * std::sin(tilt), 0.5f, 0.5f + 0.5f * std::cos(tilt)};
  scene.textures.push_back(normal_map);
  const Image image = render_direct(scene);
  const auto points = floor_points(scene);
  const vec3 expected = kRho * lamp.intensity * std::cos(tilt) / kPi;
  double worst = 0.0;
  int pixels = 0;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      if (!points[size_t(y * kWidth + x)]) continue;
      worst = std::max(worst, std::abs(double(image.at(x, y, 1)) - expected.y) / expected.y);
      ++pixels;
    }
  }
  std::printf("normal map: expected %.4g (flat %.4g), worst relative error %.2e over %d pixels\n",
              double(expected.y), double(kRho * lamp.intensity.y / kPi), worst, pixels);
  EXPECT_GT(pixels, 10000);
  EXPECT_LT(worst, 0.01);  // the texel's 8-bit-free float encoding: only shader rounding
}

// A height bump seen from afar: ridges (a height sinusoid of 16 texels across u, slopes up
// to 43 degrees) tiled 40 times over the floor, ~10 texels a pixel, under a sun 35 degrees
// off the normal across the ridges. The frames' mean over the floor must be the mean over one
// period of rho E max(0, n_b . l) / pi, with n_b the bump model's normal (central differences
// of the bilinear height, as bake/bump.cpp and shaders/bump.glsl both take them), computed
// here by quadrature. A normal taken from the pixel's averaged height lights it too brightly.
// (The floor's light does not vary: the floor mean is the mean over the ridges' phases.)
TEST(ViewerLamps, MinifiedHeightBumpKeepsItsMeanCosine) {
  const float theta = glm::radians(35.0f);
  const Lamp lamp = directional_lamp({0.0f, -std::cos(theta), -std::sin(theta)}, vec3(2.0f));
  Scene scene = lamp_floor(lamp, false);
  constexpr int kTexels = 64, kTiles = 40;
  constexpr float kScale = 0.03f;  // metres of height for a texel value of 1
  scene.textures.push_back(test::make_rgb_texture(kTexels, kTexels, [](int column, int) {
    return vec3(0.5f + 0.5f * std::sin(2.0f * kPi * float(column) / 16.0f));
  }));
  Material& floor = scene.materials[size_t(scene.meshes[0].material)];
  floor.bump = BumpKind::height;
  floor.bump_texture = 0;
  floor.bump_scale = kScale;
  for (vec2& uv : scene.meshes[0].uvs) uv *= float(kTiles);

  // u runs along +z over the 16 m quad: du/dz = kTiles / 16 per metre.
  const Texture& height = scene.textures[0];
  const float du = 1.0f / float(kTexels), uv_per_metre = float(kTiles) / 16.0f;
  const vec3 to_sun = -lamp.direction;
  double mean_cosine = 0.0;
  constexpr int kSteps = 4096;
  for (int k = 0; k < kSteps; ++k) {
    const vec2 uv((float(k) + 0.5f) / float(kSteps), 0.5f);
    const float dh_du = kScale *
                        (sample_texture(height, uv + vec2(du, 0)).x -
                         sample_texture(height, uv - vec2(du, 0)).x) /
                        (2.0f * du);
    const vec3 n = glm::normalize(vec3(0.0f, 1.0f, 0.0f) - dh_du * uv_per_metre * vec3(0, 0, 1));
    mean_cosine += std::max(0.0f, glm::dot(n, to_sun)) / double(kSteps);
  }
  const double expected = double(kRho * lamp.intensity.x) * mean_cosine / double(kPi);
  const double flat = double(kRho * lamp.intensity.x) * std::cos(theta) / double(kPi);

  const auto points = floor_points(scene);
  for (const int pixel_samples : {1, 2, 3}) {
    const Image image = render_direct(scene, pixel_samples);
    double sum = 0.0;
    int pixels = 0;
    for (int y = 0; y < kHeight; ++y)
      for (int x = 0; x < kWidth; ++x)
        if (points[size_t(y * kWidth + x)]) {
          sum += double(image.at(x, y, 0));
          ++pixels;
        }
    const double mean = sum / double(std::max(pixels, 1));
    std::printf("minified bump, %d x %d frames: floor mean %.5g, bump model %.5g (flat %.5g): "
                "%+.2f%%\n",
                pixel_samples, pixel_samples, mean, expected, flat,
                100.0 * (mean / expected - 1.0));
    EXPECT_GT(pixels, 10000);
    if (pixel_samples == 1) {
      // One frame reads a mip level (the window's smooth approximation): measured +11.1%,
      // between the model and the flat floor's +16.8% (at the pixel's own level, as every
      // frame did before 2 Dec 2026: +15.2%).
      EXPECT_GT(mean, expected);
      EXPECT_LT(mean, flat);
    } else {
      // Full-resolution bumps: measured -0.05% (2 x 2) and -0.01% (3 x 3); at the pixel's mip
      // level +15.2%, one level finer than the sub-pixel's +6.0% (2 x 2). Bound 0.5%.
      EXPECT_NEAR(mean / expected, 1.0, 0.005) << pixel_samples << " x " << pixel_samples;
    }
  }
}

// Shadow of the box from `lamp`: no light in the umbra, all of it far from the shadow.
void check_box_shadow(const Lamp& lamp, const char* name) {
  const Scene scene = lamp_floor(lamp, true);
  const Image image = render_direct(scene);
  const auto points = floor_points(scene);
  // Deep: the segment to the lamp crosses the box shrunk by 20 cm. The directional map over
  // this 16 m floor has 4.5 cm texels (512^2), and the normal offset lifts the lookup by up to
  // 4.5 texels, so a shadow edge may move by that much (measured: 0.2 % light 10 cm inside).
  const vec3 inset(0.2f), margin(0.1f);
  const vec3 peak = lamp.kind == LampKind::directional
                        ? expected_radiance(lamp, {})
                        : expected_radiance(lamp, {lamp.position.x, 0.0f, lamp.position.z});
  double umbra_max = 0.0;
  int umbra = 0;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const auto& p = points[size_t(y * kWidth + x)];
      if (!p) continue;
      if (!segment_hits_box(*p, towards_lamp_end(lamp, *p), kBoxMin + inset, kBoxMax - inset))
        continue;
      for (int k = 0; k < 3; ++k) umbra_max = std::max(umbra_max, double(image.at(x, y, k)));
      ++umbra;
    }
  }
  // Lit: clear of the grown box and above 5% of the peak (where relative errors mean something).
  const Comparison lit = compare(image, points, lamp, [&](vec3 p, vec3 e) {
    return e.x > 0.05f * peak.x &&
           !segment_hits_box(p, towards_lamp_end(lamp, p), kBoxMin - margin, kBoxMax + margin);
  });
  std::printf("%s shadow: umbra max %.3g over %d pixels; lit worst %.2e over %d pixels\n", name,
              umbra_max, umbra, lit.worst, lit.pixels);
  if (umbra_max > 0.0 || lit.worst > 0.02) {
    test::write_comparison_files(std::string("viewer_lamp_shadow_") + name, image, image);
  }
  EXPECT_GT(umbra, 100);
  EXPECT_EQ(umbra_max, 0.0);
  EXPECT_GT(lit.pixels, 2000);
  EXPECT_LT(lit.worst, 0.02);
}

TEST(ViewerLamps, PointLampBoxShadow) {
  check_box_shadow(point_lamp({-2.0f, 3.0f, 0.0f}, {10.0f, 10.0f, 10.0f}), "point");
}

TEST(ViewerLamps, SpotLampBoxShadow) {
  check_box_shadow(
      spot_lamp({-2.0f, 3.0f, 0.0f}, {3.0f, -3.0f, 0.0f}, 35.0f, 45.0f, {10.0f, 10.0f, 10.0f}),
      "spot");
}

TEST(ViewerLamps, DirectionalLampBoxShadow) {
  check_box_shadow(directional_lamp({1.0f, -0.8f, 0.3f}, {3.0f, 3.0f, 3.0f}), "directional");
}

// A spot wider than the perspective map takes (kMaxSpotMapHalfAngle) falls back to a cube.
TEST(ViewerLamps, WideSpotBoxShadowUsesACube) {
  check_box_shadow(
      spot_lamp({-2.0f, 3.0f, 0.0f}, {1.0f, -1.0f, 0.0f}, 60.0f, 75.0f, {10.0f, 10.0f, 10.0f}),
      "wide_spot");
}

// Lamps beyond kMaxShadowedLamps light the scene without shadows: eight faint lamps far away
// take the maps, so the ninth, over the box, shines into what would be its umbra.
TEST(ViewerLamps, LampsBeyondTheShadowBoundAreUnshadowed) {
  const Lamp strong = point_lamp({-2.0f, 3.0f, 0.0f}, {10.0f, 10.0f, 10.0f});
  Scene scene = lamp_floor(point_lamp({-7.0f, 1.0f, -7.0f}, vec3(1e-6f)), true);
  for (int k = 1; k < kMaxShadowedLamps; ++k) scene.lights.push_back(scene.lights[0]);
  scene.lights.push_back(strong);
  OffscreenContext context;
  Renderer renderer;
  renderer.set_scene(scene, nullptr);
  EXPECT_EQ(renderer.stats().lamps_unshadowed, 1);
  EXPECT_EQ(renderer.stats().lamp_shadow_layers, 6 * kMaxShadowedLamps);
  RenderSettings settings;
  settings.term = Term::direct;
  renderer.render(choose_camera(scene, ""), kWidth, kHeight, settings);
  const Image image = renderer.read_radiance();
  const auto points = floor_points(scene);
  // Where the box would shadow the strong lamp, it gets its full light (the faint ones add
  // under 1e-6 of it).
  const Comparison umbra = compare(image, points, strong, [&](vec3 p, vec3) {
    return segment_hits_box(p, strong.position, kBoxMin, kBoxMax);
  });
  std::printf("ninth lamp, unshadowed: worst %.2e over %d would-be umbra pixels\n", umbra.worst,
              umbra.pixels);
  EXPECT_GT(umbra.pixels, 100);
  EXPECT_LT(umbra.worst, 0.01);
}

// No lamp cap (the shader reads them from a buffer texture, viewer/light_table.h): 120
// point lamps in a 12 x 10 grid 2 m above the bare floor, 8 of them with shadow maps; every
// floor pixel is the sum of the 120 closed forms. Measured worst relative error 1.1e-6.
TEST(ViewerLamps, HundredAndTwentyLampsRender) {
  Scene scene = lamp_floor(point_lamp({0.0f, 2.0f, 0.0f}, vec3(1.0f)), false);
  scene.lights.clear();
  for (int i = 0; i < 12; ++i) {
    for (int j = 0; j < 10; ++j) {
      scene.lights.push_back(point_lamp({-5.5f + float(i), 2.0f, -4.5f + float(j)},
                                        vec3(0.05f + 0.01f * float(i), 0.05f, 0.04f)));
    }
  }
  const Image image = render_direct(scene);
  const auto points = floor_points(scene);
  double worst = 0.0;
  int pixels = 0;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const auto& p = points[size_t(y * kWidth + x)];
      if (!p) continue;
      vec3 expected(0.0f);
      for (const Lamp& lamp : scene.lights) expected += expected_radiance(lamp, *p);
      for (int k = 0; k < 3; ++k)
        worst = std::max(worst, std::abs(double(image.at(x, y, k)) - expected[k]) / expected[k]);
      ++pixels;
    }
  }
  std::printf("120 lamps: worst relative error %.2e over %d floor pixels\n", worst, pixels);
  EXPECT_GT(pixels, kWidth * kHeight / 2);
  EXPECT_LT(worst, 1e-4);
}

}  // namespace
}  // namespace lb
