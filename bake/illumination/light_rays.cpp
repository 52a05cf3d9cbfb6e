#include "bake/illumination/light_rays.h"

#include <algorithm>
#include <limits>

#include "bake/illumination/feelers.h"

namespace lb::illumination {

float light_angle_to_specular(const Scene& scene, const AreaLight& light,
                              const std::vector<Sphere>& specular) {
  const Mesh& mesh = scene.meshes[size_t(light.mesh)];
  float radius = 0.0f;
  for (uint32_t t : light.triangles)
    for (int k = 0; k < 3; ++k)
      radius = std::max(radius, glm::length(mesh.positions[mesh.triangles[t][k]] - light.centroid));
  float angle = 0.0f;
  for (const Sphere& s : specular) {
    const float distance = glm::length(s.centre - light.centroid) - s.radius;
    if (!(distance > 0.0f)) return std::numeric_limits<float>::infinity();
    angle = std::max(angle, radius / distance);
  }
  return angle;
}

LightSetup setup_light(const Scene& scene, const AreaLight& light, bool over_light_by_default,
                       const std::vector<Sphere>& specular, float max_angle) {
  LightSetup setup;
  setup.light = &light;
  setup.frame = Frame(light.normal);
  // The centre and one shared frame only make sense for a flat light.
  bool flat = true;
  const Mesh& mesh = scene.meshes[size_t(light.mesh)];
  for (uint32_t t : light.triangles)
    flat = flat && glm::dot(triangle_normal(mesh, t), light.normal) > 0.999f;
  const CausticOrigins asked = mesh.bake.caustic_origins;
  const bool over_light =
      asked == CausticOrigins::automatic
          ? over_light_by_default || light_angle_to_specular(scene, light, specular) > max_angle
          : asked == CausticOrigins::over_light;
  setup.over_light = over_light || !flat;
  setup.centre_origin = offset_ray_origin(light.centroid, light.normal, light.normal);
  return setup;
}

void light_ray(const Scene& scene, const LightSetup& setup, vec2 u_direction, vec2 u_origin,
               Ray& ray) {
  ray.tmin = 0.0f;
  ray.tmax = 1e30f;
  if (!setup.over_light) {
    ray.direction = setup.frame.to_world(square_to_cosine_hemisphere(u_direction));
    ray.origin = setup.centre_origin;
    return;
  }
  const LightSample s = setup.light->sample(scene, u_origin);
  ray.direction = Frame(s.normal).to_world(square_to_cosine_hemisphere(u_direction));
  ray.origin = offset_ray_origin(s.position, s.normal, ray.direction);
}

Ray light_ray(const Scene& scene, const LightSetup& setup, vec2 u_direction, vec2 u_origin) {
  Ray ray;
  light_ray(scene, setup, u_direction, u_origin, ray);
  return ray;
}

}  // namespace lb::illumination
