// A mirror ring standing on a floor (Figure 3's napkin ring: 5 cm tall, 4 mm wall, 0.5 mm
// above the floor) reflects the floor at its own foot, against a closed form.
//
// The floor is black inside the ring and emits 1 W/(sr m^2) from x = 0.096 m on: under the far
// wall and beyond it. The wall hides the strip under itself; in Figure 3 that strip of cloth is
// lit where nothing sees it (the shadow lookup's margin reaches past the 0.5 mm gap). Seen
// from the near side, the far wall's inner face reflects the floor inside the ring, which is
// black: the exact value is 0 wherever the reflected ray meets that floor. The ring is not in
// its own environment cube, so the cube, seen from the ring's centre 2.55 cm above the floor,
// holds the bright strip right next to the inner foot at a grazing angle, and the lookup's
// filtering carries it into the foot's reflection (the bright lines along Figure 3's ring;
// viewer/environment_cubes.cpp).

#include <gtest/gtest.h>

#include <cmath>
#include <optional>

#include "bake/io/shapes.h"
#include "test_helpers.h"
#include "viewer/offscreen_context.h"
#include "viewer/renderer.h"
#include "viewer/snapshot.h"
#include "viewer_test_scenes.h"

namespace lb {
namespace {

constexpr int kWidth = 320, kHeight = 240;
constexpr float kOuter = 0.1f, kInner = 0.096f;  // m
constexpr float kBottom = 0.0005f, kTop = 0.0505f;
constexpr float kMirrorReflectance = 0.9f;

Scene ring_scene() {
  Scene scene;
  scene.source_path = "mirror ring on a floor (in code)";
  Material bright;
  bright.reflectance = vec3(0.0f);
  bright.emission = vec3(1.0f);
  Material black;
  black.reflectance = vec3(0.0f);
  Material mirror;
  mirror.kind = MaterialKind::mirror;
  mirror.reflectance = vec3(kMirrorReflectance);
  // Floor quads facing +y: cross(edge_u, edge_v) = cross(+z, +x) = +y.
  scene.meshes.push_back(test::make_quad({kInner, 0, -2}, {0, 0, 4}, {2 - kInner, 0, 0},
                                         test::add_material(scene, bright), "bright floor"));
  scene.meshes.push_back(test::make_quad({-2, 0, -2}, {0, 0, 4}, {2 + kInner, 0, 0},
                                         test::add_material(scene, black), "black floor"));
  Mesh ring = make_cylinder(kOuter, kInner, kTop - kBottom, 192, false);
  for (vec3& p : ring.positions) p.y += 0.5f * (kTop + kBottom);
  ring.name = "ring";
  ring.material = test::add_material(scene, mirror);
  scene.meshes.push_back(std::move(ring));
  Camera camera;
  camera.position = {-0.25f, 0.3f, 0.0f};
  camera.target = {0.085f, 0.015f, 0.0f};  // the far wall's inner foot
  camera.vertical_fov_deg = 14.0f;
  scene.cameras.push_back(camera);
  return scene;
}

// Where a ray meets the infinite cylinder of radius r about the y axis, between the ring's
// bottom and top: the ray parameters, nearest first (none: +inf).
std::pair<float, float> cylinder_hits(vec3 o, vec3 d, float r) {
  const float inf = INFINITY;
  const float a = d.x * d.x + d.z * d.z, b = o.x * d.x + o.z * d.z;
  const float c = o.x * o.x + o.z * o.z - r * r, disc = b * b - a * c;
  if (a <= 0.0f || disc <= 0.0f) return {inf, inf};
  float t[2] = {(-b - std::sqrt(disc)) / a, (-b + std::sqrt(disc)) / a};
  for (float& ti : t) {
    const float y = o.y + ti * d.y;
    if (ti <= 0.0f || y < kBottom || y > kTop) ti = inf;
  }
  return {t[0], t[1]};
}

// The far wall's inner face where pixel (x, y)'s camera ray meets it first (not behind the
// near wall or the rim, not at a grazing angle), when its reflection lands on the floor
// inside the ring: the reflection's exact value is then 0.
std::optional<vec3> black_reflection_point(const ViewCamera& camera, int x, int y) {
  const Ray ray = test::camera_ray(camera, kWidth, kHeight, x, y);
  const vec3 d = glm::normalize(ray.direction);
  const auto [outer_near, outer_far] = cylinder_hits(ray.origin, d, kOuter);
  const auto [inner_near, inner_far] = cylinder_hits(ray.origin, d, kInner);
  if (!std::isfinite(inner_far) || outer_near < inner_far || inner_near < inner_far)
    return std::nullopt;
  // The rim: the ray must come down into the ring's opening, not through its top face.
  const vec3 top = ray.origin + d * ((kTop - ray.origin.y) / d.y);
  if (glm::length(vec2(top.x, top.z)) > kInner - 1e-4f) return std::nullopt;
  const vec3 p = ray.origin + inner_far * d;
  const vec3 n = -glm::normalize(vec3(p.x, 0.0f, p.z));  // the inner face looks inwards
  if (glm::dot(n, -d) < 0.3f) return std::nullopt;
  const vec3 r = glm::reflect(d, n);
  if (r.y >= 0.0f) return std::nullopt;
  const vec3 hit = p + r * (-p.y / r.y);
  if (glm::length(vec2(hit.x, hit.z)) > kInner) return std::nullopt;
  return p;
}

// Until 3 Dec 2026 every object's cube had 128^2 faces; mirrors now get 256^2. Measured here
// (green channel, W/(sr m^2); exact 0) over 28,584 pixels: 128^2 mean 0.0008, the wall's
// lowest 5 mm (2,688 pixels) 0.0085, worst 0.32; 256^2 mean 0.0001, lowest 5 mm 0.0013, worst
// 0.22 (a shorter line at the very foot). The bounds sit between.
TEST(ViewerMirrorRing, ReflectionOfTheFootKeepsWhatLiesUnderTheWallOut) {
  const Scene scene = ring_scene();
  OffscreenContext context;
  Renderer renderer;
  renderer.set_scene(scene, nullptr);
  ASSERT_EQ(renderer.stats().environment_object_cubes, 1);
  const ViewCamera camera = choose_camera(scene, "");
  renderer.render(camera, kWidth, kHeight, RenderSettings{});
  const Image image = renderer.read_radiance();

  int counted = 0, foot = 0;
  double sum = 0.0, foot_sum = 0.0, worst = 0.0;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const std::optional<vec3> p = black_reflection_point(camera, x, y);
      if (!p) continue;
      const double value = image.at(x, y, 1);
      ++counted;
      sum += value;
      worst = std::max(worst, value);
      if (p->y < kBottom + 0.005f) {
        ++foot;
        foot_sum += value;
      }
    }
  }
  std::printf("inner wall reflecting the black floor: %d pixels, mean %.4f, worst %.4f; "
              "lowest 5 mm: %d pixels, mean %.4f W/(sr m^2) (exact 0)\n",
              counted, sum / counted, worst, foot, foot_sum / std::max(foot, 1));
  ASSERT_GT(counted, 2000);
  ASSERT_GT(foot, 200);
  EXPECT_LT(sum / counted, 0.0004);
  EXPECT_LT(foot_sum / foot, 0.004);
}

}  // namespace
}  // namespace lb
