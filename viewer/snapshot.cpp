#include "viewer/snapshot.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "bake/camera.h"
#include "viewer/offscreen_context.h"
#include "viewer/renderer.h"

namespace lb {

ViewCamera choose_camera(const Scene& scene, const std::string& name_or_index) {
  return ViewCamera::from(select_camera(scene, name_or_index));
}

double max_display_difference(const Image& a, const Image& b, const ToneMap& tone) {
  if (a.width != b.width || a.height != b.height || a.channels != b.channels)
    throw std::invalid_argument("max_display_difference: images of different sizes");
  double worst = 0.0;
  for (size_t i = 0; i < a.pixels.size(); ++i) {
    const double da = srgb_oetf(tonemap_value(a.pixels[i], tone));
    const double db = srgb_oetf(tonemap_value(b.pixels[i], tone));
    worst = std::max(worst, std::abs(da - db));
  }
  return worst;
}

Image render_snapshot(const Scene& scene, const BakeResult* bake, const SnapshotOptions& options,
                      ShadowResolution* shadow_resolution) {
  if (options.width <= 0 || options.height <= 0 || options.width > 16384 ||
      options.height > 16384) {
    throw std::invalid_argument("snapshot size " + std::to_string(options.width) + "x" +
                                std::to_string(options.height) + " is out of range");
  }
  const ViewCamera camera = choose_camera(scene, options.camera);
  OffscreenContext context;
  Renderer renderer(options.shader_directory);
  // Still images of several sub-pixel frames see the lights from one interleaved set of
  // shadow points a frame (ShadowSettings::interleave); the first set comes with the scene.
  const bool stochastic = options.settings.direct_mode == DirectMode::stochastic;
  // Stochastic frames stay at the pixel centres: their estimator numbers run with the still
  // frames' index, which a moved sample point would start again.
  const int n = stochastic ? 1 : std::clamp(options.pixel_samples, 1, 16);
  const bool shadow_sets = n > 1 && options.settings.shadows;
  ShadowSettings shadows = options.shadows;
  if (shadow_sets) shadows.interleave = n;
  renderer.set_scene(scene, bake, shadows);
  if (shadow_resolution) *shadow_resolution = renderer.stats().shadow_resolution;
  // Stochastic: the running mean of `frames` frames (a refined image would be the full one).
  RenderSettings settings = options.settings;
  settings.refine_bands = 0;
  settings.bump_full_resolution = n > 1;
  const int frames = stochastic ? std::max(1, options.frames) : n * n;
  if (n == 1) {
    for (int frame = 0; frame < frames; ++frame) {
      renderer.render(camera, options.width, options.height, settings);
    }
    return renderer.read_radiance();
  }
  // Each frame at one sub-pixel centre of the grid, its image added here: a changed offset
  // starts the renderer's own accumulation again, so the mean is taken on the CPU, in double.
  std::vector<double> sum;
  Image image;
  for (int cell = 0; cell < frames; ++cell) {
    if (shadow_sets && cell > 0) {
      shadows.set = cell;
      renderer.set_shadow_points(shadows);
    }
    const vec2 offset((float(cell % n) + 0.5f) / float(n) - 0.5f,
                      (float(cell / n) + 0.5f) / float(n) - 0.5f);
    renderer.render(camera, options.width, options.height, settings, offset);
    image = renderer.read_radiance();
    sum.resize(image.pixels.size(), 0.0);
    for (size_t i = 0; i < sum.size(); ++i) sum[i] += double(image.pixels[i]);
  }
  for (size_t i = 0; i < sum.size(); ++i) image.pixels[i] = float(sum[i] / double(frames));
  return image;
}

}  // namespace lb
