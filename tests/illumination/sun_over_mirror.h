#pragma once
// The sun over a planar mirror, for pass 1's tests: the sun at theta from the vertical onto a
// 2 x 2 m mirror (z = 0, facing up); the ceiling (z = 1, facing down, x in [0.45, 1.5], so it
// shades none of the sunlit mirror that lights it; texel 0.1 m) receives it reflected, arriving
// from (-sin theta, 0, -cos theta) with irradiance R E cos(theta) at its own normal everywhere.

#include <cmath>
#include <numbers>

#include "test_helpers.h"

namespace lb::test {

struct SunOverMirror {
  Scene scene;
  float reflectance = 0.7f, irradiance = 3.0f, theta = std::numbers::pi_v<float> / 6.0f;
  SunOverMirror() {
    const int white = add_material(scene, Material{});
    Material mirror;
    mirror.kind = MaterialKind::mirror;
    mirror.reflectance = vec3(reflectance);
    const int shiny = add_material(scene, mirror);
    scene.meshes.push_back(make_quad({-1, -1, 0}, {2, 0, 0}, {0, 2, 0}, shiny, "mirror"));
    Mesh ceiling = make_quad({0.45f, -1, 1}, {0, 2, 0}, {1.05f, 0, 0}, white, "ceiling");
    ceiling.bake.texel_size = 0.1f;
    scene.meshes.push_back(ceiling);
    Lamp sun;
    sun.kind = LampKind::directional;
    sun.direction = vec3(std::sin(theta), 0, -std::cos(theta));
    sun.intensity = vec3(irradiance);
    scene.lights.push_back(sun);
  }
  vec3 from() const { return {-std::sin(theta), 0.0f, -std::cos(theta)}; }
};

}  // namespace lb::test
