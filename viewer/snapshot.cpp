#include "viewer/snapshot.h"

#include <stdexcept>

#include "bake/camera.h"
#include "viewer/offscreen_context.h"
#include "viewer/renderer.h"

namespace lb {

ViewCamera choose_camera(const Scene& scene, const std::string& name_or_index) {
  return ViewCamera::from(select_camera(scene, name_or_index));
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
