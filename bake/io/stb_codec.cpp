// Decoding through stb_image (PNG, JPEG, Radiance HDR, TGA, BMP, PSD, GIF, PIC, PNM), Radiance
// RGBE out through stb_image_write, and the dispatch between stb and OpenEXR (image_codecs.h).

#include <stb/stb_image.h>
#include <stb/stb_image_write.h>

#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <sstream>
#include <type_traits>

#include "bake/io/image_codecs.h"

namespace lb::codecs {

namespace {

constexpr const char* kHdrStampLine = "SOFTWARE=lightbake";

struct StbFree {
  void operator()(void* pixels) const { stbi_image_free(pixels); }
};

std::string stb_reason() {
  const char* reason = stbi_failure_reason();
  return reason ? reason : "unknown image format";
}

// The first `kept` of each pixel's `stored` samples as floats. Integer samples (8 or 16 bits)
// become value * (1 / max), as OpenImageIO converted them, so textures decode to the same
// floats as before the switch; float samples stay as they are.
template <typename Sample>
void copy_samples(const Sample* samples, std::vector<float>& out, int kept, int stored) {
  constexpr float kScale =
      std::is_integral_v<Sample> ? 1.0f / float(std::numeric_limits<Sample>::max()) : 1.0f;
  const size_t pixels = out.size() / size_t(kept);
  for (size_t p = 0; p < pixels; ++p)
    for (int c = 0; c < kept; ++c)
      out[p * size_t(kept) + size_t(c)] = float(samples[p * size_t(stored) + size_t(c)]) * kScale;
}

// A PNG's size from its header chunk, so an image too large for stb (which then only says
// "unknown image type") is refused with its size named. False if `head` is not a PNG.
bool png_header_size(const std::string& head, int& width, int& height, int& channels) {
  if (head.size() < 26 || head.compare(0, 8, "\x89PNG\r\n\x1a\n") != 0 ||
      head.compare(12, 4, "IHDR") != 0)
    return false;
  const auto big_endian = [&](size_t at) {
    uint32_t value = 0;
    for (size_t i = 0; i < 4; ++i) value = value << 8 | uint8_t(head[at + i]);
    return value;
  };
  const uint32_t w = big_endian(16), h = big_endian(20);
  if (w > uint32_t(INT32_MAX) || h > uint32_t(INT32_MAX)) return false;
  width = int(w);
  height = int(h);
  // Colour types 0 grey, 2 RGB, 3 palette (RGB, perhaps with alpha), 4 grey+alpha, 6 RGBA.
  static constexpr int kChannels[7] = {1, 0, 3, 3, 2, 0, 4};
  channels = uint8_t(head[25]) < 7 ? kChannels[uint8_t(head[25])] : 0;
  return true;
}

// Decodes with one of stb's *_from_memory loaders (8-bit, 16-bit or float samples) into the
// image `decoded` holds, whose size and kept channels come from the header.
template <typename Sample>
void load_samples(Sample* (*load)(const stbi_uc*, int, int*, int*, int*, int),
                  const stbi_uc* bytes, int size, int stored, Decoded& decoded) {
  int width = 0, height = 0, channels = 0;
  std::unique_ptr<Sample, StbFree> pixels(load(bytes, size, &width, &height, &channels, 0));
  if (!pixels) throw CodecError(stb_reason());
  if (width != decoded.image.width || height != decoded.image.height || channels != stored)
    throw CodecError("header and pixels disagree");
  copy_samples(pixels.get(), decoded.image.pixels, decoded.image.channels, channels);
}

// A file's bytes, read once (stb would otherwise open it for the header, the format checks and
// the pixels), up to the 2 GiB stb's memory loaders take.
std::string file_bytes(const std::string& path) {
  std::error_code error;
  const uintmax_t size = std::filesystem::file_size(path, error);
  if (error) throw CodecError(error.message());
  if (size > uintmax_t(std::numeric_limits<int>::max()))
    throw CodecError("encoded image larger than 2 GiB");
  std::string bytes(size_t(size), '\0');
  std::ifstream in(path, std::ios::binary);
  if (!in.read(bytes.data(), std::streamsize(size))) throw CodecError("cannot read the file");
  return bytes;
}

}  // namespace

std::string read_head(const Source& source, size_t size) {
  if (source.data)
    return std::string(static_cast<const char*>(source.data), std::min(size, source.size));
  std::string head(size, '\0');
  std::ifstream in(source.path, std::ios::binary);
  in.read(head.data(), std::streamsize(size));
  head.resize(size_t(std::max<std::streamsize>(in.gcount(), 0)));
  return head;
}

void check_size(int width, int height, int channels, int max_channels, uint64_t max_values) {
  const uint64_t kept = uint64_t(std::min(channels, max_channels));
  if (width <= 0 || height <= 0 || channels <= 0) throw CodecError("image has no pixels");
  if (uint64_t(width) * uint64_t(height) * kept > max_values)
    throw CodecError(std::to_string(width) + " x " + std::to_string(height) + " x " +
                     std::to_string(channels) + " values, more than the " +
                     std::to_string(max_values) + " an image may hold (bake/io/input_limits.h)");
}

Decoded decode_stb(const Source& source, int max_channels, uint64_t max_values) {
  const std::string file = source.data ? std::string() : file_bytes(source.path);
  const Source in_memory = source.data ? source : Source{source.path, file.data(), file.size()};
  if (in_memory.size > size_t(std::numeric_limits<int>::max()))
    throw CodecError("encoded image larger than 2 GiB");
  const auto* bytes = static_cast<const stbi_uc*>(in_memory.data);
  const int size = int(in_memory.size);
  int width = 0, height = 0, stored = 0;
  if (png_header_size(read_head(in_memory, 26), width, height, stored))
    check_size(width, height, std::max(stored, 1), max_channels, max_values);
  if (!stbi_info_from_memory(bytes, size, &width, &height, &stored))
    throw CodecError(stb_reason());
  check_size(width, height, stored, max_channels, max_values);

  Decoded decoded;
  const int kept = std::min(stored, max_channels);
  decoded.image = Image(width, height, kept);
  if (kept == 2 || kept == 4) decoded.alpha_channel = kept - 1;
  if (stbi_is_hdr_from_memory(bytes, size)) {
    load_samples(stbi_loadf_from_memory, bytes, size, stored, decoded);
  } else {
    decoded.display_encoded = true;
    if (stbi_is_16_bit_from_memory(bytes, size))
      load_samples(stbi_load_16_from_memory, bytes, size, stored, decoded);
    else
      load_samples(stbi_load_from_memory, bytes, size, stored, decoded);
  }
  return decoded;
}

Decoded decode(const Source& source, int max_channels, uint64_t max_values) {
  return is_exr(source) ? decode_exr(source, max_channels, max_values)
                        : decode_stb(source, max_channels, max_values);
}

bool hdr_is_stamped(const std::string& path) {
  // The header is a handful of short lines ending at an empty one, well inside 4 KiB.
  std::istringstream header(read_head({path}, 4096));
  std::string line;
  for (int i = 0; std::getline(header, line) && !line.empty(); ++i) {
    if (i == 0 && line.rfind("#?", 0) != 0) return false;
    if (line == kHdrStampLine) return true;
  }
  return false;
}

void write_hdr(const std::string& path, const Image& image) {
  std::string encoded;
  const auto append = [](void* context, void* data, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data), size_t(size));
  };
  if (!stbi_write_hdr_to_func(append, &encoded, image.width, image.height, image.channels,
                              image.pixels.data()))
    throw std::runtime_error(path + ": cannot write: RGBE encoding failed");
  // The stamp goes in the header, after the "#?RADIANCE" line.
  const size_t first_line_end = encoded.find('\n');
  if (first_line_end == std::string::npos)
    throw std::runtime_error(path + ": cannot write: RGBE encoding failed");
  encoded.insert(first_line_end + 1, std::string(kHdrStampLine) + "\n");
  std::ofstream out(path, std::ios::binary);
  out.write(encoded.data(), std::streamsize(encoded.size()));
  out.close();
  if (!out) throw std::runtime_error(path + ": cannot write");
}

}  // namespace lb::codecs
