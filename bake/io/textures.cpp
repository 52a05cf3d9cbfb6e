#include "bake/io/textures.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "bake/io/image_codecs.h"
#include "bake/io/image_io.h"
#include "bake/io/input_limits.h"
#include "bake/io/scene_load.h"

namespace lb {

namespace {

Texture decode_texture(const codecs::Source& source, bool srgb, const std::string& where) {
  codecs::Decoded decoded;
  try {
    decoded = codecs::decode(source, 4, limits::kMaxTextureValues);
  } catch (const codecs::CodecError& error) {
    throw SceneError(where + ": cannot decode texture '" + source.path +
                     "': " + first_line(error.what()));
  }
  Texture texture;
  texture.path = source.path;
  texture.width = decoded.image.width;
  texture.height = decoded.image.height;
  texture.channels = decoded.image.channels;
  texture.texels = std::move(decoded.image.pixels);
  for (float v : texture.texels)
    if (!std::isfinite(v))
      throw SceneError(where + ": texture '" + source.path + "' holds NaN or infinite values");
  // Integer formats carry display-encoded values; float formats (EXR, HDR) are linear.
  if (srgb && decoded.display_encoded) {
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
  if (const std::string problem = input_file_problem(path); !problem.empty())
    throw SceneError(where + ": texture file '" + path + "' " + problem);
  return decode_texture({path}, srgb, where);
}

Texture load_texture_memory(const void* data, size_t size, const std::string& name, bool srgb,
                            const std::string& where) {
  return decode_texture({name, data, size}, srgb, where);
}

Texture rotated_equirect(const Texture& sky, double degrees) {
  Texture out = sky;
  const int w = sky.width, c = sky.channels;
  // A right-handed turn moves what the image shows towards smaller u (u grows from -Z towards
  // +X: docs/scene-format.md): column i shows the source at i + shift.
  const double shift = degrees / 360.0 * double(w);
  const double whole = std::floor(shift);
  const float t = float(shift - whole);
  const int step = int(std::fmod(whole, double(w)) + double(w)) % std::max(w, 1);
  for (int j = 0; j < sky.height; ++j)
    for (int i = 0; i < w; ++i) {
      const int a = (i + step) % w, b = (a + 1) % w;
      const size_t row = size_t(j) * size_t(w);
      for (int k = 0; k < c; ++k)
        out.texels[(row + size_t(i)) * size_t(c) + size_t(k)] =
            (1.0f - t) * sky.texels[(row + size_t(a)) * size_t(c) + size_t(k)] +
            t * sky.texels[(row + size_t(b)) * size_t(c) + size_t(k)];
    }
  return out;
}

}  // namespace lb
