#include "bake/io/textures.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <fcntl.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <memory>

#include "bake/io/scene_load.h"

namespace lb {

float srgb_to_linear(float encoded) {
  return encoded <= 0.04045f ? encoded / 12.92f : std::pow((encoded + 0.055f) / 1.055f, 2.4f);
}

namespace {

// Integer pixel formats carry display-encoded values; float formats (EXR, HDR) are linear.
bool stores_encoded_values(const OIIO::ImageSpec& spec) {
  const OIIO::TypeDesc::BASETYPE base = OIIO::TypeDesc::BASETYPE(spec.format.basetype);
  return base != OIIO::TypeDesc::FLOAT && base != OIIO::TypeDesc::HALF &&
         base != OIIO::TypeDesc::DOUBLE;
}

// libpng prints its own "libpng error: ..." line before OpenImageIO reports the failure; the
// error we throw already says it, and a broken scene must produce exactly one line.
class SilencedStderr {
 public:
  SilencedStderr() {
    std::fflush(stderr);
    saved_ = dup(STDERR_FILENO);
    const int null = open("/dev/null", O_WRONLY);
    if (saved_ >= 0 && null >= 0) dup2(null, STDERR_FILENO);
    if (null >= 0) close(null);
  }
  ~SilencedStderr() {
    std::fflush(stderr);
    if (saved_ >= 0) {
      dup2(saved_, STDERR_FILENO);
      close(saved_);
    }
  }
  SilencedStderr(const SilencedStderr&) = delete;
  SilencedStderr& operator=(const SilencedStderr&) = delete;

 private:
  int saved_ = -1;
};

Texture read_open_image(OIIO::ImageInput& input, const std::string& name, bool srgb,
                        const std::string& where) {
  const OIIO::ImageSpec& spec = input.spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0)
    throw SceneError(where + ": texture '" + name + "' has no pixels");
  Texture texture;
  texture.path = name;
  texture.width = spec.width;
  texture.height = spec.height;
  texture.channels = std::min(spec.nchannels, 4);
  texture.texels.resize(size_t(texture.width) * size_t(texture.height) * size_t(texture.channels));
  if (!input.read_image(0, 0, 0, texture.channels, OIIO::TypeDesc::FLOAT, texture.texels.data())) {
    std::string reason = input.geterror();
    if (reason.empty()) reason = "unreadable pixel data";
    throw SceneError(where + ": cannot decode texture '" + name + "': " + reason);
  }
  for (float v : texture.texels)
    if (!std::isfinite(v))
      throw SceneError(where + ": texture '" + name + "' holds NaN or infinite values");
  if (srgb && stores_encoded_values(spec)) {
    const int colour_channels = texture.channels == 2 ? 1 : std::min(texture.channels, 3);
    for (size_t i = 0; i < texture.texels.size(); i += size_t(texture.channels))
      for (int c = 0; c < colour_channels; ++c)
        texture.texels[i + size_t(c)] = srgb_to_linear(texture.texels[i + size_t(c)]);
    texture.srgb_decoded = true;
  }
  return texture;
}

std::string first_line(std::string text) {
  const size_t newline = text.find('\n');
  if (newline != std::string::npos) text.resize(newline);
  return text;
}

}  // namespace

Texture load_texture_file(const std::string& path, bool srgb, const std::string& where) {
  if (!OIIO::Filesystem::exists(path))
    throw SceneError(where + ": texture file '" + path + "' does not exist");
  const SilencedStderr silence;
  auto input = OIIO::ImageInput::open(path);
  if (!input) {
    std::string reason = first_line(OIIO::geterror());
    if (reason.empty()) reason = "unknown image format";
    throw SceneError(where + ": cannot decode texture '" + path + "': " + reason);
  }
  Texture texture = read_open_image(*input, path, srgb, where);
  input->close();
  return texture;
}

Texture load_texture_memory(const void* data, size_t size, const std::string& name, bool srgb,
                            const std::string& where) {
  const SilencedStderr silence;
  OIIO::Filesystem::IOMemReader reader(data, size);
  // OpenImageIO picks the format from the name's extension, then sniffs the bytes.
  auto input = OIIO::ImageInput::open(name, nullptr, &reader);
  if (!input) {
    std::string reason = first_line(OIIO::geterror());
    if (reason.empty()) reason = "unknown image format";
    throw SceneError(where + ": cannot decode texture '" + name + "': " + reason);
  }
  Texture texture = read_open_image(*input, name, srgb, where);
  input->close();
  return texture;
}

}  // namespace lb
