#include "app/radiance_output.h"

#include <cctype>
#include <filesystem>

namespace lb::app {

std::string lowercase_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

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

}  // namespace lb::app
