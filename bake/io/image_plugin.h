#pragma once
// The boundary between lightbake and lightbake_images.so, the plugin that holds OpenImageIO.
// Linking OpenImageIO maps about 270 shared libraries (0.3-0.4 CPU s before main), so the
// executable links none of them: image_codecs.cpp opens the plugin with dlopen on first image
// use, and commands that read no image start in about 0.02 CPU s (docs/architecture.md).
//
// Both sides are built by the same CMake run with the same compiler and standard library, so
// the interface is plain C++; what it must not do is let an exception or a pointer to the
// plugin's own objects cross it. Every call returns "" on success or the reason it failed.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "bake/io/image_codecs.h"

namespace lb::codecs {

class ImagePlugin {
 public:
  virtual ~ImagePlugin() = default;
  // Reads the header, refuses images of more than `max_values` kept floats before decoding
  // (size_problem below), then decodes the first subimage's full-resolution level.
  virtual std::string decode(const Source& source, int max_channels, uint64_t max_values,
                             Decoded& out) const = 0;
  // codecs::encode: the file in memory (the caller writes it, so write errors and atomic
  // replacement have one place, atomic_file.h).
  virtual std::string encode(const std::string& format, const Pixels& pixels,
                             std::vector<unsigned char>& out) const = 0;
  // The file's "Software" field ("" when it has none or is not an image).
  virtual std::string software(const std::string& path) const = 0;
};

// The plugin's one exported symbol: returns its ImagePlugin when `version` is the one it was
// built with, nullptr otherwise (a plugin left from another build).
constexpr int kImagePluginVersion = 1;
constexpr const char* kImagePluginFile = "lightbake_images.so";
constexpr const char* kImagePluginEntry = "lightbake_image_plugin";
using ImagePluginEntry = const ImagePlugin* (*)(int version);

// Why an image of width x height x channels, of which at most max_channels are kept, is
// refused ("" when it is not).
inline std::string size_problem(int width, int height, int channels, int max_channels,
                                uint64_t max_values) {
  if (width <= 0 || height <= 0 || channels <= 0) return "image has no pixels";
  const uint64_t kept = uint64_t(channels < max_channels ? channels : max_channels);
  if (uint64_t(width) * uint64_t(height) * kept <= max_values) return "";
  return std::to_string(width) + " x " + std::to_string(height) + " x " +
         std::to_string(channels) + " values, more than the " + std::to_string(max_values) +
         " an image may hold (bake/io/input_limits.h)";
}

}  // namespace lb::codecs
