#include "bake/thin_lens_camera.h"

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

bool ThinLensCamera::connect(vec3 point, vec2 lens, Connection& out) const {
  vec3 origin = position_;
  if (aperture_radius_ > 0.0f) {
    const vec2 disk = aperture_radius_ * square_to_disk(lens);
    origin += disk.x * right_ + disk.y * up_;
  }
  const vec3 to_point = point - origin;
  const float depth = glm::dot(to_point, forward_);
  if (!(depth > 0.0f)) return false;
  // Where the ray meets the plane of focus, seen from the camera centre, at distance 1.
  const vec3 on_focus = origin + to_point * (focus_distance_ / depth) - position_;
  const float sx = glm::dot(on_focus, right_) / focus_distance_;
  const float sy = glm::dot(on_focus, up_) / focus_distance_;
  out.film = {(sx / half_width_ + 1.0f) * 0.5f * float(width_),
              (1.0f - sy / half_height_) * 0.5f * float(height_)};
  if (!(out.film.x >= 0.0f && out.film.x < float(width_) && out.film.y >= 0.0f &&
        out.film.y < float(height_)))
    return false;
  const float cos_theta = depth / glm::length(to_point);
  const float pixel_area =
      (2.0f * half_width_ / float(width_)) * (2.0f * half_height_ / float(height_));
  out.lens_point = origin;
  out.importance = 1.0f / (pixel_area * cos_theta * cos_theta * cos_theta);
  return true;
}

}  // namespace lb
