#pragma once
// The renderers' image output (render, reference): linear radiance to .exr (float32) or the
// shared tone mapping to .png, chosen by the path's extension.

#include <string>
#include <vector>

#include "bake/io/image_io.h"
#include "bake/scene.h"

namespace lb::app {

// The extension with its dot, lower case ("" if none).
std::string lowercase_extension(const std::string& path);

// Whether `path` ends in .exr or .png (any case).
bool is_radiance_image_path(const std::string& path);

// `pixels` (width x height, row 0 at the top, W/(sr m^2)) to `path`, atomically.
void write_radiance_image(const std::string& path, const std::vector<vec3>& pixels, int width,
                          int height, const ToneMap& tone);

}  // namespace lb::app
