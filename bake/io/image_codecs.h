#pragma once
// Image files in every format OpenImageIO reads and writes (PNG, JPEG, OpenEXR, Radiance HDR,
// TIFF of 8, 16 or 32 bits, mipmapped .tx, DDS, WebP, TGA, BMP, PSD, GIF, PNM, ...), for
// image_io.h and textures.h. OpenImageIO lives in a plugin opened on first use
// (image_plugin.h), so these calls are the only way in.
//
// decode throws CodecError with the reason only; callers put the file and place in front.

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
  std::string path;  // the file to read, or a name for messages (its extension hints the format)
  const void* data = nullptr;
  size_t size = 0;
};

struct Decoded {
  Image image;                   // at most max_channels, R, G, B, A (or Y, A) first
  bool display_encoded = false;  // integer samples (PNG, JPEG, TIFF, ...): value / max, not linear
  int alpha_channel = -1;        // index in image.channels, -1 when there is none
};

// The first subimage at full resolution (the top level of a mipmapped file). Refuses images of
// more than `max_values` floats (width * height * kept channels) from the header, before
// decoding. Integer samples become value * (1 / max) in [0,1]; float samples stay as stored;
// alpha stays straight (not premultiplied), as stored.
Decoded decode(const Source& source, int max_channels, uint64_t max_values);

// What to encode: width * height * channels samples, row-major, top row first, given as
// floats or as bytes (exactly one of the two).
struct Pixels {
  int width = 0, height = 0, channels = 0;
  const float* values = nullptr;
  const uint8_t* bytes = nullptr;
  SampleType stored = SampleType::float32;  // in the file, where the format offers it
  bool srgb = false;                        // sRGB-encoded samples: tag the file so (PNG)
};

// The encoded file, stamped with kSoftware. `format` is a format name ("png", "openexr",
// "hdr") or a file name whose extension names it. EXR is ZIP-compressed; Radiance HDR takes
// RGB (grey is repeated, alpha dropped). No time of writing is recorded: the same pixels give
// the same bytes. Throws std::runtime_error with the reason.
std::vector<unsigned char> encode(const std::string& format, const Pixels& pixels);

// The encoders stamp "lightbake" as the file's software; this reads the stamp back (false for
// other files, missing and unreadable ones included).
constexpr const char* kSoftware = "lightbake";
bool is_stamped(const std::string& path);

}  // namespace lb::codecs
