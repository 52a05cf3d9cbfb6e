#pragma once
// The image file formats behind image_io.h and textures.h, one library each:
//   OpenEXR  .exr              read and write (half or float, ZIP)
//   libpng   .png              write (8 bits, sRGB chunk, "Software" text chunk)
//   stb      .png .jpg .hdr .tga .bmp .psd .gif .pic .pnm   read; .hdr (RGBE) write
// These are small libraries the process maps in a few milliseconds; OpenImageIO, which the
// project used before, cost every command about 0.3 CPU s of start-up for formats it never
// needed (issue 16).
//
// Decoders throw CodecError with the reason only; callers put the file and place in front.
// Writers write to the path they are given (callers pass a temporary, see atomic_file.h) and
// throw std::runtime_error naming it.

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "bake/io/image_io.h"

namespace lb::codecs {

struct CodecError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Where encoded bytes come from: a file (data == nullptr) or memory.
struct Source {
  std::string path;  // the file to read, or a name for messages
  const void* data = nullptr;
  size_t size = 0;
};

struct Decoded {
  Image image;                   // at most max_channels, in R, G, B, A (or Y, A) order
  bool display_encoded = false;  // integer samples (PNG, JPEG, ...): value / max, not linear
  int alpha_channel = -1;        // index in image.channels, -1 when there is none
};

// Reads the header, refuses images of more than `max_values` floats (width * height *
// kept channels) before allocating, then decodes. Integer samples become value / max in [0,1]
// (the same float OpenImageIO gave: value * (1 / max)); float samples stay as stored.
Decoded decode(const Source& source, int max_channels, uint64_t max_values);

// The writers stamp "lightbake" as the file's software; these read that stamp back.
constexpr const char* kSoftware = "lightbake";
bool exr_is_stamped(const std::string& path);
bool png_is_stamped(const std::string& path);
bool hdr_is_stamped(const std::string& path);

void write_exr(const std::string& path, const Image& image, bool half);
void write_png(const std::string& path, int width, int height, int channels,
               const uint8_t* bytes);
void write_hdr(const std::string& path, const Image& image);

// Helpers the decoders share.
std::string read_head(const Source& source, size_t size);  // the first `size` bytes, or fewer
bool is_exr(const Source& source);  // by the file's magic number, not its name
Decoded decode_exr(const Source& source, int max_channels, uint64_t max_values);
Decoded decode_stb(const Source& source, int max_channels, uint64_t max_values);
// Throws CodecError when width * height * min(channels, max_channels) exceeds max_values.
void check_size(int width, int height, int channels, int max_channels, uint64_t max_values);

}  // namespace lb::codecs
