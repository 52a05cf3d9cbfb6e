#include "viewer/snapshot.h"

#include <stdexcept>

#include "viewer/offscreen_context.h"
#include "viewer/renderer.h"

namespace lb {

ViewCamera choose_camera(const Scene& scene, const std::string& name_or_index) {
  if (name_or_index.empty()) {
    return scene.cameras.empty() ? fit_to_scene(scene_bounds(scene))
                                 : ViewCamera::from(scene.cameras.front());
  }
  for (const Camera& camera : scene.cameras) {
    if (camera.name == name_or_index) return ViewCamera::from(camera);
  }
  if (name_or_index.find_first_not_of("0123456789") == std::string::npos) {
    const size_t index = std::stoul(name_or_index);
    if (index < scene.cameras.size()) return ViewCamera::from(scene.cameras[index]);
  }
  if (name_or_index == "fit") return fit_to_scene(scene_bounds(scene));
  std::string names;
  for (size_t i = 0; i < scene.cameras.size(); ++i) {
    names += (i ? ", " : "") + std::to_string(i) + " '" + scene.cameras[i].name + "'";
  }
  throw std::invalid_argument(scene.source_path + ": no camera '" + name_or_index +
                              "' (cameras: " + (names.empty() ? "none" : names) + "; or 'fit')");
}

Image render_snapshot(const Scene& scene, const BakeResult* bake, const SnapshotOptions& options) {
  if (options.width <= 0 || options.height <= 0 || options.width > 16384 ||
      options.height > 16384) {
    throw std::invalid_argument("snapshot size " + std::to_string(options.width) + "x" +
                                std::to_string(options.height) + " is out of range");
  }
  const ViewCamera camera = choose_camera(scene, options.camera);
  OffscreenContext context;
  Renderer renderer(options.shader_directory);
  renderer.set_scene(scene, bake, options.shadows);
  renderer.render(camera, options.width, options.height, options.settings);
  return renderer.read_radiance();
}

}  // namespace lb
