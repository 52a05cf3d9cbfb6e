#include "app/radiance_output.h"

#include <cctype>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "bake/io/atomic_file.h"
#include "bake/json_text.h"
#include "bake/binary_file.h"

namespace lb::app {

bool is_radiance_image_path(const std::string& path) {
  const std::string ext = lowercase_extension(path);
  return ext == ".exr" || ext == ".png";
}

void write_radiance_image(const std::string& path, const std::vector<vec3>& pixels, int width,
                          int height, const ToneMap& tone) {
  Image image(width, height, 3);
  for (size_t i = 0; i < pixels.size(); ++i)
    for (int c = 0; c < 3; ++c) image.pixels[i * 3 + size_t(c)] = pixels[i][c];
  if (lowercase_extension(path) == ".exr")
    write_exr(path, image, ExrPixelType::float32);
  else
    write_png_tonemapped(path, image, tone);
}

void write_radiance_image_and_report(const std::string& path, const std::vector<vec3>& pixels,
                                     int width, int height, const ToneMap& tone,
                                     const std::string& report_path, nlohmann::json report) {
  const auto write_image = [&](const std::string& temp) {
    write_radiance_image(temp, pixels, width, height, tone);
  };
  write_pair_atomic(path, write_image, report_path, [&](const std::string& image_temp) {
    const Reader image(image_temp);
    report["image"] = {{"file", std::filesystem::path(path).filename().string()},
                       {"bytes", image.size()},
                       {"fnv1a", fnv1a_hex(image.bytes())}};
    return json_text(report, 2) + "\n";
  });
}

}  // namespace lb::app
