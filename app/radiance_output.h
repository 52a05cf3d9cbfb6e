#pragma once
// The renderers' image output (render, reference): linear radiance to .exr (float32) or the
// shared tone mapping to .png, chosen by the path's extension.

#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "bake/input_file.h"  // lowercase_extension
#include "bake/io/image_io.h"
#include "bake/scene.h"

namespace lb::app {

// Whether `path` ends in .exr or .png (any case).
bool is_radiance_image_path(const std::string& path);

// `pixels` (width x height, row 0 at the top, W/(sr m^2)) to `path`, atomically.
void write_radiance_image(const std::string& path, const std::vector<vec3>& pixels, int width,
                          int height, const ToneMap& tone);

// The image and its JSON report as one pair (write_pair_atomic): both written under temporary
// names, the image renamed into place, then the report; a failure removes what this call
// published, so a new image never stays without its report. The report records the image as
// "image": {"file", "bytes", "fnv1a"}, which tells a reader a mismatched pair (one run's image
// with another's report).
void write_radiance_image_and_report(const std::string& path, const std::vector<vec3>& pixels,
                                     int width, int height, const ToneMap& tone,
                                     const std::string& report_path, nlohmann::json report);

}  // namespace lb::app
