#include "viewer/view_camera.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <optional>

#include "bake/camera.h"

namespace lb {

namespace {

constexpr float kMaxPitchRadians = kMaxOrbitPitchDeg * 3.14159265f / 180.0f;

// The distance along unit `direction` from `origin` to the first surface that faces `origin`
// (the ray meets its front side), within `max_distance`; surfaces met from behind are passed
// through, up to a few layers (a ball the point sits in, then the room around it).
std::optional<float> first_facing_hit(const Accel& accel, vec3 origin, vec3 direction,
                                      float max_distance) {
  vec3 start = origin;
  float travelled = 0.0f;  // from `origin` to `start`
  for (int layer = 0; layer < 16; ++layer) {
    const Ray ray{start, direction, 0.0f, max_distance - travelled};
    if (ray.tmax <= 0.0f) return std::nullopt;
    const std::optional<Hit> hit = accel.intersect(ray);
    if (!hit) return std::nullopt;
    if (glm::dot(hit->geometric_normal, direction) < 0.0f) return travelled + hit->t;
    // Met from behind: go on from just beyond it.
    start = offset_ray_origin(start + hit->t * direction, hit->geometric_normal, direction);
    travelled = glm::length(start - origin);
  }
  return std::nullopt;
}

vec3 direction_from_angles(float theta, float phi) {
  return vec3(std::cos(phi) * std::sin(theta), std::sin(phi), std::cos(phi) * std::cos(theta));
}

}  // namespace

ViewCamera ViewCamera::from(const Camera& camera) {
  ViewCamera view;
  view.position = camera.position;
  view.target = camera.target;
  view.up = camera.up;
  view.vertical_fov_deg = camera.vertical_fov_deg;
  return view;
}

glm::mat4 ViewCamera::view() const {
  return glm::lookAt(position, target, up);
}

glm::mat4 ViewCamera::projection(float aspect, const Bounds& bounds) const {
  float far_plane = 1.0f;
  if (!bounds.empty()) {
    for (int corner = 0; corner < 8; ++corner) {
      const vec3 p{(corner & 1) ? bounds.max.x : bounds.min.x,
                   (corner & 2) ? bounds.max.y : bounds.min.y,
                   (corner & 4) ? bounds.max.z : bounds.min.z};
      far_plane = std::max(far_plane, glm::length(p - position));
    }
  }
  far_plane *= 1.01f;
  // A 32-bit float depth buffer keeps this ratio precise enough for room-sized scenes.
  const float near_plane = far_plane * 1e-4f;
  return glm::perspective(glm::radians(vertical_fov_deg), aspect, near_plane, far_plane);
}

float room_enclosure(const Accel& accel, vec3 point) {
  // Fibonacci sphere: evenly spread, deterministic directions (golden angle 2.39996 rad).
  int enclosed = 0;
  for (int i = 0; i < kEnclosureDirections; ++i) {
    const float y = 1.0f - (2.0f * float(i) + 1.0f) / float(kEnclosureDirections);
    const float r = std::sqrt(std::max(0.0f, 1.0f - y * y));
    const float angle = 2.39996323f * float(i);
    const vec3 direction{r * std::cos(angle), y, r * std::sin(angle)};
    if (first_facing_hit(accel, point, direction, 1e30f)) ++enclosed;
  }
  return float(enclosed) / float(kEnclosureDirections);
}

float unobstructed_distance(const Accel& accel, vec3 target, vec3 direction, float wanted) {
  const std::optional<float> hit = first_facing_hit(accel, target, direction, wanted);
  if (!hit) return wanted;
  const float margin = std::max(0.02f * *hit, 1e-4f * accel.scene_scale());
  return std::min(wanted, *hit > 2.0f * margin ? *hit - margin : 0.5f * *hit);
}

ViewCamera fit_to_scene(const Bounds& bounds, float vertical_fov_deg, const Accel* accel) {
  ViewCamera outside = ViewCamera::from(fit_camera(bounds, vertical_fov_deg));
  if (!accel || bounds.empty()) return outside;
  const vec3 centre = 0.5f * (bounds.min + bounds.max);
  if (room_enclosure(*accel, centre) < kClosedRoomFraction) return outside;
  // Inside: back against the wall on the longer horizontal axis's + side, looking across.
  const vec3 extent = bounds.extent();
  const vec3 axis = extent.z >= extent.x ? vec3(0.0f, 0.0f, 1.0f) : vec3(1.0f, 0.0f, 0.0f);
  ViewCamera inside = outside;
  inside.target = centre;
  inside.position = centre + axis * unobstructed_distance(*accel, centre, axis, bounds.diagonal());
  inside.up = vec3(0.0f, 1.0f, 0.0f);
  return inside;
}

void orbit(ViewCamera& camera, float yaw, float pitch, const Accel* accel) {
  const vec3 offset = camera.position - camera.target;
  const float radius = glm::length(offset);
  const float wanted = camera.orbit_distance > 0.0f ? camera.orbit_distance : radius;
  const float theta = std::atan2(offset.x, offset.z) - yaw;
  float phi = std::asin(std::clamp(offset.y / std::max(radius, 1e-9f), -1.0f, 1.0f)) + pitch;
  phi = std::clamp(phi, -kMaxPitchRadians, kMaxPitchRadians);
  const vec3 direction = direction_from_angles(theta, phi);
  const float distance =
      accel ? unobstructed_distance(*accel, camera.target, direction, wanted) : wanted;
  camera.position = camera.target + distance * direction;
  camera.orbit_distance = wanted;
  camera.up = vec3(0.0f, 1.0f, 0.0f);
}

void zoom(ViewCamera& camera, float factor, const Accel* accel) {
  const vec3 offset = camera.position - camera.target;
  const float radius = glm::length(offset);
  if (radius <= 0.0f) return;
  const float wanted = (camera.orbit_distance > 0.0f ? camera.orbit_distance : radius) * factor;
  const vec3 direction = offset / radius;
  const float distance =
      accel ? unobstructed_distance(*accel, camera.target, direction, wanted) : wanted;
  camera.position = camera.target + distance * direction;
  // Zooming out against a wall is not remembered: zooming back in acts at once.
  camera.orbit_distance = distance < wanted ? 0.0f : wanted;
}

float orbit_pitch_deg(const ViewCamera& camera) {
  const vec3 offset = camera.position - camera.target;
  const float radius = std::max(glm::length(offset), 1e-9f);
  return glm::degrees(std::asin(std::clamp(offset.y / radius, -1.0f, 1.0f)));
}

void fly(ViewCamera& camera, vec3 forward_right_up) {
  const vec3 forward = camera.forward();
  const vec3 right = glm::normalize(glm::cross(forward, camera.up));
  const vec3 up = glm::cross(right, forward);
  const vec3 move =
      forward * forward_right_up.x + right * forward_right_up.y + up * forward_right_up.z;
  camera.position += move;
  camera.target += move;
}

void look(ViewCamera& camera, float yaw, float pitch) {
  const vec3 offset = camera.target - camera.position;
  const float distance = glm::length(offset);
  const float theta = std::atan2(offset.x, offset.z) - yaw;
  float phi = std::asin(std::clamp(offset.y / std::max(distance, 1e-9f), -1.0f, 1.0f)) + pitch;
  phi = std::clamp(phi, -kMaxPitchRadians, kMaxPitchRadians);
  camera.target = camera.position + distance * direction_from_angles(theta, phi);
  camera.up = vec3(0.0f, 1.0f, 0.0f);
}

}  // namespace lb
