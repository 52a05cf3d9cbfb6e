#pragma once
// Every light of a scene behind the two questions the passes ask of a light:
//   emit()           a ray leaving the light with the power it carries (passes 1 and 2, light
//                    tracing in the reference);
//   sample_towards() a point of the light seen from a receiver, with its density (HQ mode's
//                    direct light, next-event estimation in the reference).
// Kinds: area lights (emissive meshes, bake/lights.h), lamps (point, spot, directional) and the
// sky. A new kind is a case here, not a change in every pass.
//
// Lights at infinity (directional, sky) send their rays from a disk just outside the scene's
// bounding sphere, facing the ray direction, so every ray that can reach the scene is sent and
// none is wasted far away; their power() is the power that crosses that disk.

#include <cstddef>
#include <limits>
#include <memory>
#include <vector>

#include "bake/accel.h"
#include "bake/lights.h"
#include "bake/scene.h"
#include "bake/sky_light.h"

namespace lb {

enum class LightKind : uint8_t { area, point, spot, directional, sky };

const char* to_string(LightKind kind);

// One ray from a light. Its expected `power` over uniform u is the light's whole power(): a
// pass that sends N rays gives each power / N. A lamp with a `range` fades with the distance
// its ray travels before the first hit: multiply by range_window(distance) there.
struct EmittedRay {
  vec3 origin{0.0f};
  vec3 direction{0.0f, 0.0f, 1.0f};  // unit
  vec3 power{0.0f};                  // W per channel
};

// A light seen from a receiver. For a delta light (point, spot, directional) `radiance` is the
// irradiance it gives a surface facing it (W/m^2) and `pdf` is 1; otherwise `radiance` is the
// emitted radiance along `direction` (W/(sr m^2)) and `pdf` its solid-angle density (1/sr).
// Either way the receiver gets f * radiance * cos(theta) / pdf, visibility permitting.
struct LightTowards {
  vec3 direction{0.0f};  // unit, from the receiver towards the light
  float distance =
      std::numeric_limits<float>::infinity();  // to the light's point; inf: at infinity
  vec3 radiance{0.0f};
  float pdf = 0.0f;  // 0: no light this way (behind an area light, outside a spot's cone)
  bool delta = false;
};

// The sphere that bounds the scene's geometry, for lights at infinity.
struct BoundingSphere {
  vec3 centre{0.0f};
  float radius = 1.0f;
};
BoundingSphere bounding_sphere(const Scene& scene);

// glTF's spot falloff: 1 inside the inner cone, 0 outside the outer one, and between them the
// square of a linear ramp in cos(angle) (the KHR_lights_punctual recommendation).
float spot_falloff(const Lamp& lamp, float cos_angle);
// glTF's range window, clamp(1 - (d / range)^4, 0, 1)^2 with the inverse square law applied
// apart (1 for no range): the recommended smooth cutoff.
float range_window(const Lamp& lamp, float distance);
// Radiant intensity of a point or spot lamp towards unit `direction` (from the lamp), W/sr.
vec3 intensity_towards(const Lamp& lamp, vec3 direction);
// Power of a point or spot lamp, W per channel: 4 pi I, or I times the cone's weighted solid
// angle 2 pi ((1 - cos inner) + (cos inner - cos outer) / 3). Range windows are not counted.
vec3 lamp_power(const Lamp& lamp);

class LightSources {
 public:
  explicit LightSources(const Scene& scene);

  size_t size() const { return entries_.size(); }
  bool empty() const { return entries_.empty(); }
  LightKind kind(size_t light) const { return entries_[light].kind; }
  // W per channel (lights at infinity: the power that crosses the scene's bounding disk).
  vec3 power(size_t light) const { return entries_[light].power; }
  vec3 total_power() const;
  // The lamp behind a point, spot or directional light, the area light behind an area light.
  const Lamp& lamp(size_t light) const { return scene_.lights[size_t(entries_[light].index)]; }
  const AreaLight& area_light(size_t light) const { return area_[size_t(entries_[light].index)]; }
  // The area lights alone, in order: entries 0 .. area_lights().size() - 1.
  const std::vector<AreaLight>& area_lights() const { return area_; }
  const SkyLight* sky() const { return sky_.get(); }
  const BoundingSphere& bounds() const { return bounds_; }

  // A ray from `light`: u_origin picks the start (area lights, the disk of lights at infinity),
  // u_direction the direction.
  EmittedRay emit(size_t light, vec2 u_origin, vec2 u_direction) const;
  // `light` seen from `receiver`; u picks the point (area lights, sky).
  LightTowards sample_towards(size_t light, vec3 receiver, vec2 u) const;
  // The distance factor of a ray from `light` that travelled `distance` (range_window for
  // lamps with a range, else 1).
  float range_window(size_t light, float distance) const;

 private:
  struct Entry {
    LightKind kind;
    int index;  // into area_ or scene_.lights; -1 for the sky
    vec3 power;
  };
  const Scene& scene_;
  BoundingSphere bounds_;
  std::vector<AreaLight> area_;
  std::unique_ptr<SkyLight> sky_;
  std::vector<Entry> entries_;
};

// The shadow ray from a receiver on a surface (`from`, its geometric normal) towards a light
// without a surface, as sample_towards() returned it: a lamp's point (ends exactly there) or a
// light at infinity (no end). Area lights need segment_ray with the light point's normal.
Ray shadow_ray_towards(vec3 from, vec3 from_normal, const LightTowards& towards);

}  // namespace lb
