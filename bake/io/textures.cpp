#include "bake/io/textures.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <memory>

#include "bake/io/image_io.h"
#include "bake/io/input_limits.h"
#include "bake/io/scene_load.h"

namespace lb {

namespace {

// Integer pixel formats carry display-encoded values; float formats (EXR, HDR) are linear.
bool stores_encoded_values(const OIIO::ImageSpec& spec) {
  const OIIO::TypeDesc::BASETYPE base = OIIO::TypeDesc::BASETYPE(spec.format.basetype);
  return base != OIIO::TypeDesc::FLOAT && base != OIIO::TypeDesc::HALF &&
         base != OIIO::TypeDesc::DOUBLE;
}

Texture read_open_image(OIIO::ImageInput& input, const std::string& name, bool srgb,
                        const std::string& where) {
  const OIIO::ImageSpec& spec = input.spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0)
    throw SceneError(where + ": texture '" + name + "' has no pixels");
  const uint64_t values =
      uint64_t(spec.width) * uint64_t(spec.height) * uint64_t(std::min(spec.nchannels, 4));
  if (values > limits::kMaxTextureValues)
    throw SceneError(where + ": texture '" + name + "' is " + std::to_string(spec.width) + " x " +
                     std::to_string(spec.height) + " x " + std::to_string(spec.nchannels) +
                     " values, more than the " + std::to_string(limits::kMaxTextureValues) +
                     " a texture may hold (bake/io/input_limits.h)");
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
        texture.texels[i + size_t(c)] = srgb_eotf(texture.texels[i + size_t(c)]);
    texture.srgb_decoded = true;
  }
  return texture;
}

}  // namespace

Texture load_texture_file(const std::string& path, bool srgb, const std::string& where) {
  if (!OIIO::Filesystem::exists(path))
    throw SceneError(where + ": texture file '" + path + "' does not exist");
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
