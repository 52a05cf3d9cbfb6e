#include "bake/camera.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace lb {

Camera fit_camera(const Bounds& bounds, float vertical_fov_deg) {
  Camera camera;
  camera.name = "fit";
  camera.vertical_fov_deg = vertical_fov_deg;
  if (bounds.empty()) return camera;
  const vec3 centre = 0.5f * (bounds.min + bounds.max);
  const float radius = 0.5f * std::max(bounds.diagonal(), 1e-3f);
  // The bounding sphere just fits the vertical field of view.
  const float distance = radius / std::sin(glm::radians(vertical_fov_deg) * 0.5f);
  camera.target = centre;
  camera.position = centre + distance * glm::normalize(vec3(0.0f, 0.35f, 1.0f));
  return camera;
}

Camera select_camera(const Scene& scene, const std::string& name_or_index) {
  if (name_or_index.empty())
    return scene.cameras.empty() ? fit_camera(scene_bounds(scene)) : scene.cameras.front();
  for (const Camera& camera : scene.cameras)
    if (camera.name == name_or_index) return camera;
  if (name_or_index.find_first_not_of("0123456789") == std::string::npos &&
      name_or_index.size() < 9) {
    const size_t index = std::stoul(name_or_index);
    if (index < scene.cameras.size()) return scene.cameras[index];
  }
  if (name_or_index == "fit") return fit_camera(scene_bounds(scene));
  std::string names;
  for (size_t i = 0; i < scene.cameras.size(); ++i)
    names += (i ? ", " : "") + std::to_string(i) + " '" + scene.cameras[i].name + "'";
  throw std::invalid_argument(scene.source_path + ": no camera '" + name_or_index +
                              "' (cameras: " + (names.empty() ? "none" : names) + "; or 'fit')");
}

}  // namespace lb
