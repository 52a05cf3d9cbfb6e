#include "bake/hq/camera.h"

#include <cmath>
#include <glm/gtc/constants.hpp>
#include <stdexcept>

#include "bake/sampling.h"

namespace lb {

ThinLensCamera::ThinLensCamera(const Camera& camera, int width, int height)
    : position_(camera.position), width_(width), height_(height) {
  if (width <= 0 || height <= 0) throw std::invalid_argument("camera: image size must be positive");
  const vec3 view = camera.target - camera.position;
  const float view_length = glm::length(view);
  forward_ = view_length > 0.0f ? view / view_length : vec3(0, 0, -1);
  vec3 right = glm::cross(forward_, camera.up);
  // An up vector parallel to the view direction: pick any perpendicular one.
  if (glm::length(right) < 1e-6f)
    right = glm::cross(forward_, std::abs(forward_.y) < 0.9f ? vec3(0, 1, 0) : vec3(1, 0, 0));
  right_ = glm::normalize(right);
  up_ = glm::cross(right_, forward_);
  half_height_ = std::tan(glm::radians(camera.vertical_fov_deg) * 0.5f);
  half_width_ = half_height_ * float(width) / float(height);
  aperture_radius_ = std::max(camera.aperture_radius, 0.0f);
  focus_distance_ = camera.focus_distance > 0.0f ? camera.focus_distance
                                                 : (view_length > 0.0f ? view_length : 1.0f);
}

Ray ThinLensCamera::generate(vec2 film, vec2 lens) const {
  Ray ray;
  generate(film, lens, ray);
  return ray;
}

void ThinLensCamera::generate(vec2 film, vec2 lens, Ray& ray) const {
  const float sx = (2.0f * film.x / float(width_) - 1.0f) * half_width_;
  const float sy = (1.0f - 2.0f * film.y / float(height_)) * half_height_;
  const vec3 pinhole_direction = forward_ + sx * right_ + sy * up_;
  ray.tmin = 0.0f;
  ray.tmax = 1e30f;
  if (aperture_radius_ <= 0.0f) {
    ray.origin = position_;
    ray.direction = glm::normalize(pinhole_direction);
    return;
  }
  // The point on the plane of focus (forward distance focus_distance_) stays sharp.
  const vec3 focus_point = position_ + focus_distance_ * pinhole_direction;
  const vec2 disk = aperture_radius_ * square_to_disk(lens);
  const vec3 origin = position_ + disk.x * right_ + disk.y * up_;
  ray.origin = origin;
  ray.direction = glm::normalize(focus_point - origin);
}

}  // namespace lb
