#include "viewer/view_camera.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>

#include "bake/camera.h"

namespace lb {

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

ViewCamera fit_to_scene(const Bounds& bounds, float vertical_fov_deg) {
  return ViewCamera::from(fit_camera(bounds, vertical_fov_deg));
}

void orbit(ViewCamera& camera, float yaw, float pitch) {
  vec3 offset = camera.position - camera.target;
  const float radius = glm::length(offset);
  float theta = std::atan2(offset.x, offset.z) - yaw;
  float phi = std::asin(std::clamp(offset.y / std::max(radius, 1e-9f), -1.0f, 1.0f)) + pitch;
  phi = std::clamp(phi, -1.55f, 1.55f);
  offset = radius *
           vec3(std::cos(phi) * std::sin(theta), std::sin(phi), std::cos(phi) * std::cos(theta));
  camera.position = camera.target + offset;
  camera.up = vec3(0.0f, 1.0f, 0.0f);
}

void zoom(ViewCamera& camera, float factor) {
  camera.position = camera.target + (camera.position - camera.target) * factor;
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
  float theta = std::atan2(offset.x, offset.z) - yaw;
  float phi = std::asin(std::clamp(offset.y / std::max(distance, 1e-9f), -1.0f, 1.0f)) + pitch;
  phi = std::clamp(phi, -1.55f, 1.55f);
  camera.target = camera.position + distance * vec3(std::cos(phi) * std::sin(theta), std::sin(phi),
                                                    std::cos(phi) * std::cos(theta));
  camera.up = vec3(0.0f, 1.0f, 0.0f);
}

}  // namespace lb
