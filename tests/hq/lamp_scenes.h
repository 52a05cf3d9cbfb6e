#pragma once
// Lamp scenes for HQ mode's and the reference's tests, built in code: a white floor seen from
// straight above, lamps pushed into Scene::lights by the test, and the closed forms of
// docs/lights (the lead's brief, issue 14) averaged over a pixel's footprint on the floor.

#include <functional>

#include "bake/scene.h"

namespace lb::test {

// A 2 half_size x 2 half_size m floor in the plane y = 0 facing up (reflectance rho), and
// `camera` straight above its centre at `camera_height` m looking down (+x to the right, -z up
// in the image) with a field of view that shows the floor's middle `view_half` m each way.
Scene make_lamp_floor(float rho, float half_size, float camera_height, float view_half,
                      Camera& camera);

Lamp point_lamp(vec3 position, float intensity);  // W/sr, every channel
// A spot pointing straight down; cones in radians.
Lamp spot_lamp(vec3 position, float intensity, float inner_cone, float outer_cone);
// A directional lamp of irradiance `irradiance` W/m^2 (every channel) travelling along `direction`.
Lamp directional_lamp(vec3 direction, float irradiance);

// The point lamp's closed form on the floor: rho I h / (pi (h^2 + r^2)^(3/2)), W/(sr m^2).
double point_lamp_radiance(double rho, double intensity, double height, double r);

// The mean of value(floor point) over pixel (x, y) of a width x height image from `camera`
// (an 8 x 8 grid over the pixel), and whether every grid point and the pixel's corners pass
// `keep` (false: a mixed pixel, to skip).
struct FloorPixel {
  double mean = 0.0;
  bool kept = false;
};
FloorPixel floor_pixel(const Camera& camera, int width, int height, int x, int y,
                       const std::function<double(glm::dvec3)>& value,
                       const std::function<bool(glm::dvec3)>& keep);

// Pixel values (grey) against `value` over the pixels `keep` passes whole: the worst relative
// error (absolute where the closed form is 0: then `worst_zero`), and the pixel counts.
struct FloorComparison {
  double worst = 0.0;       // relative, over pixels with a positive closed form
  double worst_zero = 0.0;  // absolute, W/(sr m^2), over pixels where it is 0
  int pixels = 0, zero_pixels = 0;
};
FloorComparison compare_floor(const std::function<double(int x, int y)>& pixel_value,
                              const Camera& camera, int width, int height,
                              const std::function<double(glm::dvec3)>& value,
                              const std::function<bool(glm::dvec3)>& keep);

}  // namespace lb::test
