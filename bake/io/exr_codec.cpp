// OpenEXR in and out (image_codecs.h).

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIO.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfTestFile.h>
#include <OpenEXR/ImfVersion.h>
#include <Imath/half.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <vector>

#include "bake/io/image_codecs.h"

namespace lb::codecs {

namespace {

// Encoded EXR bytes held by the caller (a glTF buffer view), read in place.
class MemoryStream final : public Imf::IStream {
 public:
  MemoryStream(const std::string& name, const void* data, size_t size)
      : Imf::IStream(name.c_str()), data_(static_cast<const char*>(data)), size_(size) {}

  bool isMemoryMapped() const override { return true; }
  char* readMemoryMapped(int n) override {
    const char* at = take(n);
    return const_cast<char*>(at);  // OpenEXR's interface; it only reads through the pointer
  }
  bool read(char c[], int n) override {
    std::memcpy(c, take(n), size_t(n));
    return position_ < size_;
  }
  uint64_t tellg() override { return position_; }
  void seekg(uint64_t position) override {
    if (position > size_) throw CodecError("seek past the end of the data");
    position_ = position;
  }

 private:
  const char* take(int n) {
    if (n < 0 || uint64_t(n) > size_ - position_) throw CodecError("data ends early");
    const char* at = data_ + position_;
    position_ += uint64_t(n);
    return at;
  }

  const char* data_;
  uint64_t size_;
  uint64_t position_ = 0;
};

// The file's channels in the order an RGBA image wants them: R, G, B, A when there is colour,
// Y, A for luminance, otherwise the file's own (alphabetical) order.
std::vector<std::string> channel_order(const Imf::ChannelList& channels) {
  std::vector<std::string> names;
  for (auto it = channels.begin(); it != channels.end(); ++it) names.emplace_back(it.name());
  const auto has = [&](const char* name) {
    return std::find(names.begin(), names.end(), name) != names.end();
  };
  std::vector<std::string> ordered;
  for (const char* name : {"R", "G", "B", "Y", "A"})
    if (has(name)) ordered.emplace_back(name);
  if (ordered.empty() || (ordered.size() == 1 && ordered[0] == "A")) return names;
  return ordered;
}

Decoded read_input(Imf::InputFile& file, int max_channels, uint64_t max_values) {
  const Imath::Box2i window = file.header().dataWindow();
  const int64_t width = int64_t(window.max.x) - window.min.x + 1;
  const int64_t height = int64_t(window.max.y) - window.min.y + 1;
  if (width <= 0 || height <= 0 || width > INT32_MAX || height > INT32_MAX)
    throw CodecError("empty or invalid data window");
  const std::vector<std::string> names = channel_order(file.header().channels());
  if (names.empty()) throw CodecError("no channels");
  check_size(int(width), int(height), int(names.size()), max_channels, max_values);

  Decoded decoded;
  const int kept = std::min(int(names.size()), max_channels);
  decoded.image = Image(int(width), int(height), kept);
  Imf::FrameBuffer frame;
  const size_t x_stride = sizeof(float) * size_t(kept);
  for (int c = 0; c < kept; ++c) {
    const Imf::Channel& channel = file.header().channels()[names[size_t(c)]];
    if (channel.xSampling != 1 || channel.ySampling != 1)
      throw CodecError("subsampled channel '" + names[size_t(c)] + "' is not supported");
    if (names[size_t(c)] == "A") decoded.alpha_channel = c;
    frame.insert(names[size_t(c)], Imf::Slice::Make(Imf::FLOAT, decoded.image.pixels.data() + c,
                                                    window, x_stride, x_stride * size_t(width)));
  }
  file.setFrameBuffer(frame);
  file.readPixels(window.min.y, window.max.y);
  return decoded;
}

}  // namespace

bool is_exr(const Source& source) {
  const std::string magic = read_head(source, 4);
  return magic.size() == 4 && Imf::isImfMagic(magic.data());
}

Decoded decode_exr(const Source& source, int max_channels, uint64_t max_values) {
  try {
    if (source.data) {
      MemoryStream stream(source.path, source.data, source.size);
      Imf::InputFile file(stream);
      return read_input(file, max_channels, max_values);
    }
    Imf::InputFile file(source.path.c_str());
    return read_input(file, max_channels, max_values);
  } catch (const CodecError&) {
    throw;
  } catch (const std::exception& error) {
    throw CodecError(error.what());
  }
}

bool exr_is_stamped(const std::string& path) {
  try {
    if (!Imf::isOpenExrFile(path.c_str())) return false;
    Imf::InputFile file(path.c_str());
    const auto* software = file.header().findTypedAttribute<Imf::StringAttribute>("Software");
    return software && software->value() == kSoftware;
  } catch (const std::exception&) {
    return false;
  }
}

void write_exr(const std::string& path, const Image& image, bool half) {
  static constexpr std::array<std::array<const char*, 4>, 4> kNames = {{
      {"Y"}, {"R", "G"}, {"R", "G", "B"}, {"R", "G", "B", "A"}}};
  try {
    Imf::Header header(image.width, image.height);
    header.compression() = Imf::ZIP_COMPRESSION;
    header.insert("Software", Imf::StringAttribute(kSoftware));
    // OpenEXR writes a channel from a slice of its own type, so halves are rounded here
    // (Imath's round to nearest even, as OpenImageIO did).
    std::vector<Imath::half> halves;
    if (half) halves.assign(image.pixels.begin(), image.pixels.end());
    const Imf::PixelType type = half ? Imf::HALF : Imf::FLOAT;
    const size_t value_size = half ? sizeof(Imath::half) : sizeof(float);
    // OpenEXR's slices take a mutable pointer; writing only reads through it.
    char* base = half ? reinterpret_cast<char*>(halves.data())
                      : const_cast<char*>(reinterpret_cast<const char*>(image.pixels.data()));
    const size_t x_stride = value_size * size_t(image.channels);
    Imf::FrameBuffer frame;
    for (int c = 0; c < image.channels; ++c) {
      const char* name = kNames[size_t(image.channels - 1)][size_t(c)];
      header.channels().insert(name, Imf::Channel(type));
      frame.insert(name, Imf::Slice(type, base + size_t(c) * value_size, x_stride,
                                    x_stride * size_t(image.width)));
    }
    Imf::OutputFile file(path.c_str(), header);
    file.setFrameBuffer(frame);
    file.writePixels(image.height);
  } catch (const std::exception& error) {
    throw std::runtime_error(path + ": cannot write: " + error.what());
  }
}

}  // namespace lb::codecs
