#include "bake/illumination/light_rays.h"

namespace lb::illumination {

LightSetup setup_light(const Scene& scene, const AreaLight& light, bool over_light_by_default) {
  LightSetup setup;
  setup.light = &light;
  setup.frame = Frame(light.normal);
  // The centre and one shared frame only make sense for a flat light.
  bool flat = true;
  const Mesh& mesh = scene.meshes[size_t(light.mesh)];
  for (uint32_t t : light.triangles)
    flat = flat && glm::dot(triangle_normal(mesh, t), light.normal) > 0.999f;
  const CausticOrigins asked = mesh.bake.caustic_origins;
  const bool over_light = asked == CausticOrigins::automatic
                              ? over_light_by_default
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
