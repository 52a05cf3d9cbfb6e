// The raster direct term against a closed form: a 1 m square light 2 m above a floor, half of
// it hidden from part of the floor by a square plate 1 m up. Seen from a floor point p, the
// plate projects onto the light's plane as a rectangle (scaled by 2 from p), so the visible
// light is the light less that rectangle's overlap: E/pi = L (F(light) - F(overlap)), each F
// Lambert's polygon formula evaluated here in double (independent of shaders/lights.glsl's
// float code and of the shadow cubes). Every floor pixel is then unoccluded, umbra or penumbra
// with an exact value, at its centre or averaged over the 2 x 2 sub-pixel centres.

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>

#include "test_helpers.h"
#include "viewer/snapshot.h"

namespace lb {
namespace {

constexpr int kWidth = 160, kHeight = 120;
constexpr double kRadiance = 10.0, kReflectance = 0.5;
constexpr double kLight = 0.5, kLightY = 2.0, kPlateY = 1.0;  // light [-0.5, 0.5]^2 at y = 2
constexpr double kPlateX0 = -1.5, kPlateX1 = 0.0, kPlateZ0 = -1.5, kPlateZ1 = 1.5;

using dvec3 = std::array<double, 3>;

double dot(const dvec3& a, const dvec3& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
dvec3 cross(const dvec3& a, const dvec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

// E / (pi L) at floor point (x, 0, z), normal +y, from the rectangle [x0, x1] x [z0, z1] at
// height kLightY (all of it above the horizon): sum of theta_i * (n . gamma_i) / (2 pi).
double rectangle_factor(double x, double z, double x0, double x1, double z0, double z1) {
  if (x1 <= x0 || z1 <= z0) return 0.0;
  const std::array<dvec3, 4> v = {dvec3{x0 - x, kLightY, z0 - z}, dvec3{x1 - x, kLightY, z0 - z},
                                  dvec3{x1 - x, kLightY, z1 - z}, dvec3{x0 - x, kLightY, z1 - z}};
  double sum = 0.0;
  for (int i = 0; i < 4; ++i) {
    const dvec3& a = v[size_t(i)];
    const dvec3& b = v[size_t((i + 1) % 4)];
    const dvec3 c = cross(a, b);
    const double len = std::sqrt(dot(c, c));
    sum += std::atan2(len, dot(a, b)) * c[1] / len;
  }
  return std::abs(sum) / (2.0 * M_PI);
}

// R * E/pi at floor point (x, z), the plate's shadow included.
double exact_floor(double x, double z, double* unoccluded = nullptr) {
  const double full = rectangle_factor(x, z, -kLight, kLight, -kLight, kLight);
  // The plate seen from p, on the light's plane: p + (q - p) * kLightY / kPlateY.
  const double s = kLightY / kPlateY;
  const double bx0 = std::max(-kLight, x + s * (kPlateX0 - x));
  const double bx1 = std::min(kLight, x + s * (kPlateX1 - x));
  const double bz0 = std::max(-kLight, z + s * (kPlateZ0 - z));
  const double bz1 = std::min(kLight, z + s * (kPlateZ1 - z));
  const double blocked = rectangle_factor(x, z, bx0, bx1, bz0, bz1);
  if (unoccluded) *unoccluded = kReflectance * kRadiance * full;
  return kReflectance * kRadiance * (full - blocked);
}

Scene make_plate_scene() {
  Scene scene;
  scene.source_path = "plate over a floor (in code)";
  Material floor;
  floor.name = "floor";
  floor.reflectance = vec3(float(kReflectance));
  const int floor_id = test::add_material(scene, floor);
  Material lamp;
  lamp.name = "lamp";
  lamp.reflectance = vec3(0.0f);
  lamp.emission = vec3(float(kRadiance));
  const int lamp_id = test::add_material(scene, lamp);
  scene.meshes.push_back(test::make_quad({-4, 0, -4}, {0, 0, 8}, {8, 0, 0}, floor_id, "floor"));
  const float l = float(kLight), ly = float(kLightY);
  scene.meshes.push_back(test::make_quad({-l, ly, -l}, {2 * l, 0, 0}, {0, 0, 2 * l}, lamp_id));
  scene.meshes.push_back(test::make_quad({float(kPlateX0), float(kPlateY), float(kPlateZ0)},
                                         {float(kPlateX1 - kPlateX0), 0, 0},
                                         {0, 0, float(kPlateZ1 - kPlateZ0)}, floor_id, "plate"));
  Camera camera;
  camera.name = "low";
  camera.position = {0.0f, 0.9f, 2.6f};
  camera.target = {0.0f, 0.0f, -0.2f};
  camera.vertical_fov_deg = 60.0f;
  scene.cameras.push_back(camera);
  return scene;
}

// Where the ray through image point (px, py) (pixels, top left origin) meets the floor.
bool floor_point(const ViewCamera& camera, double px, double py, double& x, double& z) {
  const vec3 forward = camera.forward();
  const vec3 right = glm::normalize(glm::cross(forward, camera.up));
  const vec3 up = glm::cross(right, forward);
  const double t = std::tan(glm::radians(double(camera.vertical_fov_deg)) * 0.5);
  const double ndc_x = 2.0 * px / kWidth - 1.0, ndc_y = 1.0 - 2.0 * py / kHeight;
  const double aspect = double(kWidth) / kHeight;
  dvec3 d;
  for (int c = 0; c < 3; ++c)
    d[size_t(c)] = forward[c] + right[c] * ndc_x * t * aspect + up[c] * ndc_y * t;
  if (d[1] >= -1e-6) return false;
  const double s = -double(camera.position.y) / d[1];
  x = camera.position.x + s * d[0];
  z = camera.position.z + s * d[2];
  return std::abs(x) < 3.5 && std::abs(z) < 3.5;
}

struct Errors {
  double lit = 0, umbra = 0, penumbra = 0, penumbra_sum = 0, penumbra_exact_sum = 0;
  int lit_n = 0, umbra_n = 0, penumbra_n = 0;
};

Errors measure(int pixel_samples) {
  const Scene scene = make_plate_scene();
  SnapshotOptions options;
  options.width = kWidth;
  options.height = kHeight;
  options.settings.term = Term::direct;
  options.pixel_samples = pixel_samples;
  const Image image = render_snapshot(scene, nullptr, options);
  const ViewCamera camera = choose_camera(scene, "");
  const int n = pixel_samples;
  Errors e;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      double exact = 0.0, full = 0.0;
      bool floor = true;
      for (int j = 0; j < n && floor; ++j) {
        for (int i = 0; i < n && floor; ++i) {
          double fx = 0.0, fz = 0.0, u = 0.0;  // unset off the floor, where the pixel is dropped
          floor = floor_point(camera, x + (i + 0.5) / n, y + (j + 0.5) / n, fx, fz);
          exact += exact_floor(fx, fz, &u) / (n * n);
          full += u / (n * n);
        }
      }
      if (!floor) continue;
      const double got = image.at(x, y, 0);
      const double v = exact / full;  // the exact visible fraction
      if (v > 1.0 - 1e-9) {
        e.lit += std::abs(got - exact) / exact;
        ++e.lit_n;
      } else if (v < 1e-9) {
        e.umbra += got / full;
        ++e.umbra_n;
      } else {
        e.penumbra += std::abs(got - exact) / full;  // in units of the unoccluded light
        e.penumbra_sum += got;
        e.penumbra_exact_sum += exact;
        ++e.penumbra_n;
      }
    }
  }
  e.lit /= std::max(e.lit_n, 1);
  e.umbra /= std::max(e.umbra_n, 1);
  e.penumbra /= std::max(e.penumbra_n, 1);
  std::printf(
      "pixel samples %d: unoccluded %d px, mean rel. error %.5f; umbra %d px, mean %.5f "
      "of the unoccluded light; penumbra %d px, mean abs. error %.4f of the unoccluded "
      "light, sum ratio %.4f\n",
      n, e.lit_n, e.lit, e.umbra_n, e.umbra, e.penumbra_n, e.penumbra,
      e.penumbra_sum / e.penumbra_exact_sum);
  return e;
}

TEST(ViewerPenumbra, DirectTermMatchesTheClosedFormOfAPlateShadow) {
  const Errors centre = measure(1);
  const Errors box = measure(2);
  for (const Errors* e : {&centre, &box}) {
    ASSERT_GT(e->lit_n, 1000);
    ASSERT_GT(e->umbra_n, 1000);
    ASSERT_GT(e->penumbra_n, 1000);
    EXPECT_LT(e->lit, 3e-4);    // float closed form against double: measured 2.0e-4
    EXPECT_LT(e->umbra, 1e-3);  // measured 0 (no light leaks under the plate)
  }
  // One set of 16 jittered points (seed 1): the penumbra is made of their steps and is 7.5%
  // too bright in sum for this realisation (seeds 2..5: -4.9% .. +4.8%, mean -0.2%), mean
  // error 7.4% of the unoccluded light. Four interleaved sets of 16 (the 2 x 2 sub-pixel
  // frames): 1.9% and +1.2% (seeds 2..5: 1.6-2.7%, -1.1% .. +1.4%).
  EXPECT_LT(centre.penumbra, 0.09);
  EXPECT_NEAR(centre.penumbra_sum / centre.penumbra_exact_sum, 1.0, 0.10);
  EXPECT_LT(box.penumbra, 0.03);
  EXPECT_NEAR(box.penumbra_sum / box.penumbra_exact_sum, 1.0, 0.03);
  EXPECT_LT(box.penumbra, 0.5 * centre.penumbra);
}

}  // namespace
}  // namespace lb
