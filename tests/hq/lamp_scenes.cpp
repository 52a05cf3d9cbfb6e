#include "lamp_scenes.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "bake/thin_lens_camera.h"
#include "test_helpers.h"

namespace lb::test {

Scene make_lamp_floor(float rho, float half_size, float camera_height, float view_half,
                      Camera& camera) {
  Scene scene;
  Material floor;
  floor.name = "floor";
  floor.reflectance = vec3(rho);
  const int material = add_material(scene, floor);
  scene.meshes.push_back(make_quad({-half_size, 0, half_size}, {2 * half_size, 0, 0},
                                   {0, 0, -2 * half_size}, material, "floor"));
  camera.position = vec3(0.0f, camera_height, 0.0f);
  camera.target = vec3(0.0f);
  camera.up = vec3(0.0f, 0.0f, -1.0f);
  camera.vertical_fov_deg =
      float(2.0 * std::atan(double(view_half) / double(camera_height)) * 180.0 / std::numbers::pi);
  return scene;
}

Lamp point_lamp(vec3 position, float intensity) {
  Lamp lamp;
  lamp.kind = LampKind::point;
  lamp.position = position;
  lamp.intensity = vec3(intensity);
  return lamp;
}

Lamp spot_lamp(vec3 position, float intensity, float inner_cone, float outer_cone) {
  Lamp lamp = point_lamp(position, intensity);
  lamp.kind = LampKind::spot;
  lamp.direction = vec3(0.0f, -1.0f, 0.0f);
  lamp.inner_cone = inner_cone;
  lamp.outer_cone = outer_cone;
  return lamp;
}

Lamp directional_lamp(vec3 direction, float irradiance) {
  Lamp lamp;
  lamp.kind = LampKind::directional;
  lamp.direction = glm::normalize(direction);
  lamp.intensity = vec3(irradiance);
  return lamp;
}

double point_lamp_radiance(double rho, double intensity, double height, double r) {
  return rho * intensity * height / (std::numbers::pi * std::pow(height * height + r * r, 1.5));
}

FloorPixel floor_pixel(const Camera& camera, int width, int height, int x, int y,
                       const std::function<double(glm::dvec3)>& value,
                       const std::function<bool(glm::dvec3)>& keep) {
  const ThinLensCamera lens(camera, width, height);
  auto on_floor = [&](vec2 film, glm::dvec3& point) {
    const Ray ray = lens.generate(film, {0.5f, 0.5f});
    const double t = -double(ray.origin.y) / double(ray.direction.y);
    point = glm::dvec3(ray.origin) + t * glm::dvec3(ray.direction);
    return t > 0.0;
  };
  FloorPixel pixel;
  glm::dvec3 point;
  for (int corner = 0; corner < 4; ++corner)
    if (!on_floor(vec2(float(x + corner % 2), float(y + corner / 2)), point) || !keep(point))
      return pixel;
  constexpr int n = 8;
  double sum = 0.0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const vec2 film(float(x) + (float(i) + 0.5f) / n, float(y) + (float(j) + 0.5f) / n);
      if (!on_floor(film, point) || !keep(point)) return pixel;
      sum += value(point);
    }
  pixel.mean = sum / (n * n);
  pixel.kept = true;
  return pixel;
}

FloorComparison compare_floor(const std::function<double(int x, int y)>& pixel_value,
                              const Camera& camera, int width, int height,
                              const std::function<double(glm::dvec3)>& value,
                              const std::function<bool(glm::dvec3)>& keep) {
  FloorComparison c;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const FloorPixel expected = floor_pixel(camera, width, height, x, y, value, keep);
      if (!expected.kept) continue;
      const double got = pixel_value(x, y);
      if (expected.mean > 0.0) {
        c.worst = std::max(c.worst, std::abs(got / expected.mean - 1.0));
        ++c.pixels;
      } else {
        c.worst_zero = std::max(c.worst_zero, std::abs(got));
        ++c.zero_pixels;
      }
    }
  return c;
}

}  // namespace lb::test
