#include "bake/illumination/light_rays.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "bake/illumination/feelers.h"

namespace lb::illumination {

float light_radius(const Scene& scene, const AreaLight& light) {
  const Mesh& mesh = scene.meshes[size_t(light.mesh)];
  float radius = 0.0f;
  for (uint32_t t : light.triangles)
    for (int k = 0; k < 3; ++k)
      radius = std::max(radius, glm::length(mesh.positions[mesh.triangles[t][k]] - light.centroid));
  return radius;
}

float light_angle_to_specular(const Scene& scene, const AreaLight& light,
                              const std::vector<Sphere>& specular) {
  const float radius = light_radius(scene, light);
  float angle = 0.0f;
  for (const Sphere& s : specular) {
    const float distance = glm::length(s.centre - light.centroid) - s.radius;
    if (!(distance > 0.0f)) return std::numeric_limits<float>::infinity();
    angle = std::max(angle, radius / distance);
  }
  return angle;
}

LightSetup setup_light(const Scene& scene, const AreaLight& light,
                       const std::vector<Sphere>& specular) {
  LightSetup setup;
  setup.light = &light;
  setup.power = light.power;
  setup.frame = Frame(light.normal);
  // The centre and one shared frame only make sense for a flat light.
  bool flat = true;
  const Mesh& mesh = scene.meshes[size_t(light.mesh)];
  for (uint32_t t : light.triangles)
    flat = flat && glm::dot(triangle_normal(mesh, t), light.normal) > 0.999f;
  const CausticOrigins asked = mesh.bake.caustic_origins;
  const bool over_light =
      asked == CausticOrigins::automatic
          ? light_angle_to_specular(scene, light, specular) > kCentreOriginMaxAngle
          : asked == CausticOrigins::over_light;
  setup.over_light = over_light || !flat;
  setup.flat = flat;
  setup.radius = light_radius(scene, light);
  setup.centre_origin = offset_ray_origin(light.centroid, light.normal, light.normal);
  return setup;
}

LightSetup split_off_back(LightSetup& front) {
  front.power *= 0.5f;
  LightSetup back = front;
  back.side = -1.0f;
  back.frame = Frame(-front.light->normal);
  back.centre_origin =
      offset_ray_origin(front.light->centroid, -front.light->normal, -front.light->normal);
  return back;
}

namespace {
float max_channel(vec3 v) {
  return std::max({v.x, v.y, v.z});
}
// [0, 1) from an azimuth in radians.
float azimuth_to_unit(float y, float x) {
  const float t = std::atan2(y, x) / (2.0f * std::numbers::pi_v<float>);
  return t < 0.0f ? t + 1.0f : std::min(t, 0.99999994f);
}
}  // namespace

LightSetup setup_lamp(const LightSources& sources, size_t light) {
  LightSetup setup;
  setup.sources = &sources;
  setup.source = light;
  setup.power = sources.power(light);
  setup.unit_power = max_channel(setup.power);
  const LightKind kind = sources.kind(light);
  setup.wraps = kind == LightKind::point || kind == LightKind::spot;
  if (kind == LightKind::directional) {
    setup.zones_on_disk = true;
    setup.direction = sources.lamp(light).direction;
  }
  return setup;
}

LightSetup setup_sky_direction(const LightSources& sources, size_t light, vec2 u_direction,
                               int directions) {
  LightSetup setup;
  setup.sources = &sources;
  setup.source = light;
  setup.zones_on_disk = true;
  setup.fixed_u_direction = u_direction;
  const EmittedRay e = sources.emit(light, vec2(0.5f), u_direction);
  setup.direction = e.direction;
  setup.power = e.power / float(directions);
  setup.unit_power = max_channel(e.power);
  return setup;
}

float light_ray(const Scene& scene, const LightSetup& setup, vec2 u_zone, vec2 u_other, Ray& ray) {
  ray.tmin = 0.0f;
  ray.tmax = 1e30f;
  if (setup.sources) {
    const EmittedRay e = setup.zones_on_disk
                             ? setup.sources->emit(setup.source, u_zone, setup.fixed_u_direction)
                             : setup.sources->emit(setup.source, u_other, u_zone);
    ray.origin = e.origin;
    ray.direction = e.direction;
    return setup.unit_power > 0.0f ? max_channel(e.power) / setup.unit_power : 0.0f;
  }
  if (!setup.over_light) {
    ray.direction = setup.frame.to_world(square_to_cosine_hemisphere(u_zone));
    ray.origin = setup.centre_origin;
    return 1.0f;
  }
  const LightSample s = setup.light->sample(scene, u_other);
  ray.direction = Frame(setup.side * s.normal).to_world(square_to_cosine_hemisphere(u_zone));
  ray.origin = offset_ray_origin(s.position, s.normal, ray.direction);
  return 1.0f;
}

Ray light_ray(const Scene& scene, const LightSetup& setup, vec2 u_zone, vec2 u_other) {
  Ray ray;
  light_ray(scene, setup, u_zone, u_other, ray);
  return ray;
}

bool square_towards(const LightSetup& setup, vec3 target, vec2& u) {
  if (!setup.sources) return false;
  if (setup.zones_on_disk) {
    // LightSources' disk: centre - direction * R + (tangent, bitangent) * square_to_disk(u) * R.
    const BoundingSphere& bounds = setup.sources->bounds();
    const Frame frame(setup.direction);
    const vec3 q = target - bounds.centre;
    const vec2 d = vec2(glm::dot(q, frame.tangent), glm::dot(q, frame.bitangent)) / bounds.radius;
    if (glm::length(d) >= 1.0f) return false;
    u = disk_to_square(d);
    return true;
  }
  const Lamp& lamp = setup.sources->lamp(setup.source);
  const vec3 to_target = target - lamp.position;
  const float distance = glm::length(to_target);
  if (!(distance > 0.0f)) return false;
  const vec3 d = to_target / distance;
  // Inverse of LightSources::emit's cone map: cos theta = 1 - u.x (1 - cos_max), phi = 2 pi u.y,
  // about world +z for a point lamp, in Frame(direction) for a spot.
  if (setup.sources->kind(setup.source) == LightKind::point) {
    u = vec2(std::clamp(0.5f * (1.0f - d.z), 0.0f, 0.99999994f), azimuth_to_unit(d.y, d.x));
    return true;
  }
  const float cos_outer = std::cos(lamp.outer_cone);
  const vec3 local = Frame(lamp.direction).to_local(d);
  const float x = (1.0f - local.z) / std::max(1e-7f, 1.0f - cos_outer);
  if (x >= 1.0f) return false;
  u = vec2(std::max(x, 0.0f), azimuth_to_unit(local.y, local.x));
  return true;
}

}  // namespace lb::illumination
