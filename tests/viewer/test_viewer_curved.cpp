// Curved mirrors through their own environment cube with parallax correction
// (viewer/environment_cubes.h, shaders/environment.glsl), against a closed form.
//
// A mirror sphere (r = 0.5 m, reflectance 0.9) 0.1 m above a floor whose part z > 0.5 m (from
// below the sphere's front towards the camera) emits 1 W/(sr m^2) and whose part z < 0.5 m is
// black; nothing else, no sky. Every sphere pixel's
// exact value is 0.9 if its camera ray, reflected off the true sphere, meets the bright part
// and 0 otherwise. A cube lookup by direction alone reads the floor where the ray from the
// sphere's centre lands: the edge z = 0.5 m does not pass through the centre, so the
// reflected edge moves (the closed form below says how many pixels that puts on the wrong
// side); the parallax-corrected lookup follows the ray from the sphere's surface.

#include <gtest/gtest.h>

#include <cmath>
#include <optional>

#include "test_helpers.h"
#include "viewer/offscreen_context.h"
#include "viewer/renderer.h"
#include "viewer/snapshot.h"
#include "viewer_test_scenes.h"

namespace lb {
namespace {

constexpr int kWidth = 160, kHeight = 120;
constexpr float kEdgeZ = 0.5f;  // m: the bright part's edge on the floor, under the sphere's front
constexpr float kMirrorReflectance = 0.9f;
const vec3 kCentre(0.0f, 0.6f, 0.0f);
constexpr float kRadius = 0.5f;

Scene mirror_sphere_scene() {
  Scene scene;
  scene.source_path = "curved mirror scene (in code)";
  Material bright;
  bright.reflectance = vec3(0.0f);
  bright.emission = vec3(1.0f);
  Material black;
  black.reflectance = vec3(0.0f);
  Material mirror;
  mirror.kind = MaterialKind::mirror;
  mirror.reflectance = vec3(kMirrorReflectance);
  // Floor quads facing +y: cross(edge_u, edge_v) = cross(+z, +x) = +y.
  scene.meshes.push_back(test::make_quad({-10, 0, kEdgeZ}, {0, 0, 10 - kEdgeZ}, {20, 0, 0},
                                         test::add_material(scene, bright), "bright floor"));
  scene.meshes.push_back(test::make_quad({-10, 0, -10}, {0, 0, 10 + kEdgeZ}, {20, 0, 0},
                                         test::add_material(scene, black), "black floor"));
  scene.meshes.push_back(
      test::make_sphere(kCentre, kRadius, 96, 192, test::add_material(scene, mirror), false));
  Camera camera;
  camera.position = {0.0f, 0.6f, 1.8f};

  camera.target = kCentre;
  camera.vertical_fov_deg = 35.0f;
  scene.cameras.push_back(camera);
  return scene;
}

std::optional<float> sphere_hit(vec3 origin, vec3 direction) {
  const vec3 oc = origin - kCentre;
  const float b = glm::dot(oc, direction), c = glm::dot(oc, oc) - kRadius * kRadius;
  const float disc = b * b - c;
  if (disc <= 0.0f) return std::nullopt;
  return -b - std::sqrt(disc);
}

// The floor's radiance seen from `origin` along `direction` (unit): 1 on the bright part.
float floor_seen(vec3 origin, vec3 direction, float* z_hit = nullptr) {
  if (direction.y >= 0.0f) return 0.0f;
  const vec3 hit = origin + direction * (-origin.y / direction.y);
  if (z_hit) *z_hit = hit.z;
  return hit.z > kEdgeZ && hit.z < 10.0f && std::abs(hit.x) < 10.0f ? 1.0f : 0.0f;
}

TEST(ViewerCurved, MirrorSphereReflectsTheFloorWhereTheRayLands) {
  const Scene scene = mirror_sphere_scene();
  const ViewCamera camera = choose_camera(scene, "");
  OffscreenContext context;
  Renderer renderer;
  renderer.set_scene(scene, nullptr);
  EXPECT_EQ(renderer.stats().environment_object_cubes, 1);
  renderer.render(camera, kWidth, kHeight, RenderSettings{});
  const Image image = renderer.read_radiance();

  // Pixels well inside the sphere's outline whose exact reflection lands on the floor, more
  // than 2 cm from the edge (the tessellated sphere's normals are within ~0.1 degree of the
  // true ones; the cube's texels are ~1 degree): the value there is 0 or 0.9, no blend.
  int counted = 0, wrong = 0, wrong_direction_only = 0;
  double error_sum = 0.0;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const Ray ray = test::camera_ray(camera, kWidth, kHeight, x, y);
      const vec3 d = glm::normalize(ray.direction);
      const std::optional<float> t = sphere_hit(ray.origin, d);
      if (!t) continue;
      const vec3 p = ray.origin + *t * d;
      const vec3 n = (p - kCentre) / kRadius;
      if (glm::dot(n, -d) < 0.3f) continue;  // near the outline
      const vec3 r = glm::reflect(d, n);
      if (r.y >= 0.0f) continue;  // sees nothing: right by any lookup
      float z_hit = 0.0f;
      const float exact = kMirrorReflectance * floor_seen(p, r, &z_hit);
      if (std::abs(z_hit - kEdgeZ) < 0.02f) continue;
      const float direction_only = kMirrorReflectance * floor_seen(kCentre, r);
      const float raster = image.at(x, y, 1);
      ++counted;
      error_sum += std::abs(raster - exact);
      wrong += std::abs(raster - exact) > 0.5f * kMirrorReflectance;
      wrong_direction_only += direction_only != exact;
    }
  }
  const double wrong_fraction = double(wrong) / double(counted);
  const double direction_only_fraction = double(wrong_direction_only) / double(counted);
  std::printf(
      "mirror sphere: %d pixels, %.2f%% on the wrong side of the edge (a direction-only lookup: "
      "%.2f%%), mean |raster - exact| %.4f W/(sr m^2)\n",
      counted, 100.0 * wrong_fraction, 100.0 * direction_only_fraction,
      error_sum / double(counted));
  ASSERT_GT(counted, 3000);  // measured 4152
  // The test can tell: a direction-only lookup (the viewer before per-object cubes) puts
  // 18.1% of them on the wrong side.
  EXPECT_GT(direction_only_fraction, 0.1);
  EXPECT_LT(wrong_fraction, 0.005);              // measured 0.14%
  EXPECT_LT(error_sum / double(counted), 0.01);  // measured 0.0029 W/(sr m^2)
}

}  // namespace
}  // namespace lb
