#include "bake/light_sources.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>

#include "bake/constants.h"
#include "bake/sampling.h"

namespace lb {

namespace {

// Uniform direction in the cone of half-angle acos(cos_max) about +z, pdf 1 / (2 pi (1 - cos_max)).
vec3 square_to_cone(vec2 u, float cos_max) {
  const float cos_theta = 1.0f - u.x * (1.0f - cos_max);
  const float sin_theta = std::sqrt(std::max(0.0f, 1.0f - cos_theta * cos_theta));
  const float phi = 2.0f * kPi * u.y;
  return {sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta};
}

// A point of the disk of radius `radius` just outside the bounding sphere, upstream of rays
// travelling along `direction`.
vec3 disk_origin(const BoundingSphere& bounds, vec3 direction, vec2 u) {
  const Frame frame(direction);
  const vec2 d = square_to_disk(u) * bounds.radius;
  return bounds.centre - direction * bounds.radius + frame.tangent * d.x + frame.bitangent * d.y;
}
}  // namespace

const char* to_string(LightKind kind) {
  switch (kind) {
    case LightKind::area:
      return "area";
    case LightKind::point:
      return "point";
    case LightKind::spot:
      return "spot";
    case LightKind::directional:
      return "directional";
    case LightKind::sky:
      return "sky";
  }
  return "?";
}

BoundingSphere bounding_sphere(const Scene& scene) {
  const Bounds box = scene_bounds(scene);
  if (box.empty()) return {};
  // 1% margin, so rays from the disk start outside every surface.
  return {0.5f * (box.min + box.max), std::max(0.505f * box.diagonal(), 1e-3f)};
}

float spot_falloff(const Lamp& lamp, float cos_angle) {
  if (lamp.kind != LampKind::spot) return 1.0f;
  const float cos_outer = std::cos(lamp.outer_cone);
  const float cos_inner = std::cos(lamp.inner_cone);
  const float scale = 1.0f / std::max(0.001f, cos_inner - cos_outer);
  const float t = std::clamp((cos_angle - cos_outer) * scale, 0.0f, 1.0f);
  return t * t;
}

float range_window(const Lamp& lamp, float distance) {
  if (!(lamp.range > 0.0f) || lamp.kind == LampKind::directional) return 1.0f;
  const float r = distance / lamp.range;
  const float w = std::clamp(1.0f - r * r * r * r, 0.0f, 1.0f);
  return w * w;
}

vec3 intensity_towards(const Lamp& lamp, vec3 direction) {
  return lamp.intensity * spot_falloff(lamp, glm::dot(direction, lamp.direction));
}

vec3 lamp_power(const Lamp& lamp) {
  switch (lamp.kind) {
    case LampKind::point:
      return 4.0f * kPi * lamp.intensity;
    case LampKind::spot: {
      // Integral of the falloff over the sphere; the ramp t^2 with t linear in cos integrates
      // to a third of its width (the 0.001 floor of spot_falloff included).
      const double cos_outer = std::cos(double(lamp.outer_cone));
      const double cos_inner = std::cos(double(lamp.inner_cone));
      const double width = std::max(0.001, cos_inner - cos_outer);
      const double full = 1.0 - std::min(1.0, cos_outer + width);
      const double solid_angle = 2.0 * std::numbers::pi * (full + width / 3.0);
      return float(solid_angle) * lamp.intensity;
    }
    case LampKind::directional:
      return vec3(0.0f);  // per unit area: see LightSources::power
  }
  return vec3(0.0f);
}

LightSources::LightSources(const Scene& scene)
    : scene_(scene), bounds_(bounding_sphere(scene)), area_(collect_lights(scene)) {
  for (size_t i = 0; i < area_.size(); ++i)
    entries_.push_back({LightKind::area, int(i), area_[i].power});
  const float disk_area = kPi * bounds_.radius * bounds_.radius;
  for (size_t i = 0; i < scene.lights.size(); ++i) {
    const Lamp& lamp = scene.lights[i];
    switch (lamp.kind) {
      case LampKind::point:
        entries_.push_back({LightKind::point, int(i), lamp_power(lamp)});
        break;
      case LampKind::spot:
        entries_.push_back({LightKind::spot, int(i), lamp_power(lamp)});
        break;
      case LampKind::directional:
        entries_.push_back({LightKind::directional, int(i), lamp.intensity * disk_area});
        break;
    }
  }
  if (scene.sky) {
    const Texture* image =
        scene.sky->texture >= 0 ? &scene.textures.at(size_t(scene.sky->texture)) : nullptr;
    sky_ = std::make_unique<SkyLight>(*scene.sky, image);
    entries_.push_back({LightKind::sky, -1, sky_->integral() * disk_area});
  }
}

vec3 LightSources::total_power() const {
  vec3 sum(0.0f);
  for (const Entry& e : entries_) sum += e.power;
  return sum;
}

float LightSources::range_window(size_t light, float distance) const {
  const Entry& e = entries_[light];
  if (e.kind != LightKind::point && e.kind != LightKind::spot) return 1.0f;
  return lb::range_window(scene_.lights[size_t(e.index)], distance);
}

EmittedRay LightSources::emit(size_t light, vec2 u_origin, vec2 u_direction) const {
  const Entry& e = entries_[light];
  EmittedRay ray;
  switch (e.kind) {
    case LightKind::area: {
      // Uniform over the area, cosine-weighted about the normal: every ray carries the same power.
      // A two-sided light sends half its rays (all of its power each) from its back.
      const AreaLight& area = area_[size_t(e.index)];
      const LightSample s = area.sample(scene_, u_origin);
      const float side = area.pick_side(u_direction.x);
      ray.origin = s.position;
      ray.direction = Frame(side * s.normal).to_world(square_to_cosine_hemisphere(u_direction));
      ray.power = e.power;
      break;
    }
    case LightKind::point: {
      const Lamp& lamp = scene_.lights[size_t(e.index)];
      ray.origin = lamp.position;
      ray.direction = square_to_cone(u_direction, -1.0f);  // the whole sphere
      ray.power = e.power;
      break;
    }
    case LightKind::spot: {
      // Uniform in the outer cone, weighted by the falloff: intensity / pdf.
      const Lamp& lamp = scene_.lights[size_t(e.index)];
      const float cos_outer = std::cos(lamp.outer_cone);
      ray.origin = lamp.position;
      ray.direction = Frame(lamp.direction).to_world(square_to_cone(u_direction, cos_outer));
      const float solid_angle = 2.0f * kPi * (1.0f - cos_outer);
      ray.power = intensity_towards(lamp, ray.direction) * solid_angle;
      break;
    }
    case LightKind::directional: {
      const Lamp& lamp = scene_.lights[size_t(e.index)];
      ray.direction = lamp.direction;
      ray.origin = disk_origin(bounds_, lamp.direction, u_origin);
      ray.power = e.power;
      break;
    }
    case LightKind::sky: {
      float pdf = 0.0f;
      const vec3 to_sky = sky_->sample(u_direction, pdf);
      ray.direction = -to_sky;
      ray.origin = disk_origin(bounds_, ray.direction, u_origin);
      const float disk_area = kPi * bounds_.radius * bounds_.radius;
      ray.power = pdf > 0.0f ? sky_->radiance(to_sky) * disk_area / pdf : vec3(0.0f);
      break;
    }
  }
  return ray;
}

LightTowards LightSources::sample_towards(size_t light, vec3 receiver, vec2 u) const {
  const Entry& e = entries_[light];
  LightTowards t;
  switch (e.kind) {
    case LightKind::area: {
      const AreaLight& area = area_[size_t(e.index)];
      const LightSample s = area.sample(scene_, u);
      const vec3 to_light = s.position - receiver;
      const float d2 = glm::dot(to_light, to_light);
      if (!(d2 > 0.0f)) return t;
      t.distance = std::sqrt(d2);
      t.direction = to_light / t.distance;
      const float cos_light = area.emitting_cosine(s.normal, -t.direction);
      if (!(cos_light > 0.0f)) return t;  // its back (one-sided): no light
      t.radiance = area.radiance;
      t.pdf = s.pdf_area * d2 / cos_light;
      break;
    }
    case LightKind::point:
    case LightKind::spot: {
      const Lamp& lamp = scene_.lights[size_t(e.index)];
      const vec3 to_light = lamp.position - receiver;
      const float d2 = glm::dot(to_light, to_light);
      if (!(d2 > 0.0f)) return t;
      t.distance = std::sqrt(d2);
      t.direction = to_light / t.distance;
      t.radiance = intensity_towards(lamp, -t.direction) * lb::range_window(lamp, t.distance) / d2;
      t.delta = true;
      t.pdf = t.radiance == vec3(0.0f) ? 0.0f : 1.0f;
      break;
    }
    case LightKind::directional: {
      const Lamp& lamp = scene_.lights[size_t(e.index)];
      t.direction = -lamp.direction;
      t.radiance = lamp.intensity;
      t.delta = true;
      t.pdf = 1.0f;
      break;
    }
    case LightKind::sky: {
      float pdf = 0.0f;
      t.direction = sky_->sample(u, pdf);
      t.radiance = sky_->radiance(t.direction);
      t.pdf = pdf;
      break;
    }
  }
  return t;
}

Ray shadow_ray_towards(vec3 from, vec3 from_normal, const LightTowards& towards) {
  if (std::isinf(towards.distance)) {
    Ray ray;
    ray.origin = offset_ray_origin(from, from_normal, towards.direction);
    ray.direction = towards.direction;
    return ray;  // tmax 1e30: to infinity
  }
  return segment_ray(from, from_normal, from + towards.direction * towards.distance, vec3(0.0f));
}

}  // namespace lb
