#pragma once
// Rays leaving a light for pass 1: directions from the unit square (where the feeler zones
// live) through the concentric disk onto the light's cosine-weighted hemisphere, from the
// light's centre or from stratified points over it.

#include <vector>

#include "bake/accel.h"
#include "bake/lights.h"
#include "bake/sampling.h"

namespace lb::illumination {

struct Sphere;  // feelers.h (which includes this header)

// Where a light's rays start and which frame their directions live in.
struct LightSetup {
  const AreaLight* light = nullptr;
  bool over_light = false;
  Frame frame{vec3(0, 0, 1)};
  // Rays from the centre all leave on the light's front side, so they share one origin.
  vec3 centre_origin{0.0f};
};

// Origins over the whole light if the light's mesh asks for them (MeshBakeSettings), else if
// `over_light_by_default`, else if the light's radius over its distance to the nearest of
// `specular` (bounding spheres) exceeds `max_angle` (radians): seen from there the light is
// not a point. A light that is not flat always gets them.
LightSetup setup_light(const Scene& scene, const AreaLight& light, bool over_light_by_default,
                       const std::vector<Sphere>& specular, float max_angle);

// The light's radius (farthest vertex from its centroid) over its distance to the nearest
// bounding sphere's surface; infinity when the light reaches into one, 0 with none.
float light_angle_to_specular(const Scene& scene, const AreaLight& light,
                              const std::vector<Sphere>& specular);

// A ray leaving the light: `u_direction` in the unit square (zones live there), `u_origin`
// picks the point on the light when origins are spread over it. Written in place: a returned
// Ray copied into an array stalls on store forwarding.
void light_ray(const Scene& scene, const LightSetup& setup, vec2 u_direction, vec2 u_origin,
               Ray& ray);
Ray light_ray(const Scene& scene, const LightSetup& setup, vec2 u_direction, vec2 u_origin);

}  // namespace lb::illumination
