// lightbake_images.so: image files through OpenImageIO (image_plugin.h). The only file that
// includes OpenImageIO; it calls nothing of lightbake's outside the headers it includes, so the
// plugin links OpenImageIO alone.

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <memory>

#include "bake/io/image_plugin.h"

namespace lb::codecs {

namespace {

using OIIO::ImageInput;
using OIIO::ImageOutput;
using OIIO::ImageSpec;
using OIIO::TypeDesc;

// OpenImageIO's messages may span lines and end in a newline; ours are one line.
std::string one_line(std::string text, const char* otherwise) {
  std::replace(text.begin(), text.end(), '\n', ' ');
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text.empty() ? otherwise : text;
}

TypeDesc file_type(SampleType sample) {
  switch (sample) {
    case SampleType::uint8:
      return TypeDesc::UINT8;
    case SampleType::uint16:
      return TypeDesc::UINT16;
    case SampleType::half:
      return TypeDesc::HALF;
    case SampleType::float32:
      return TypeDesc::FLOAT;
  }
  return TypeDesc::FLOAT;
}

// Radiance HDR holds RGB: grey is repeated, alpha dropped (as stb_image_write did).
std::vector<float> to_rgb(const Pixels& pixels) {
  const size_t count = size_t(pixels.width) * size_t(pixels.height);
  const int channels = pixels.channels;
  std::vector<float> rgb(count * 3);
  for (size_t p = 0; p < count; ++p)
    for (int c = 0; c < 3; ++c)
      rgb[p * 3 + size_t(c)] = pixels.values[p * size_t(channels) + size_t(channels < 3 ? 0 : c)];
  return rgb;
}

// The Radiance header has no software field that OpenImageIO writes or reads; lightbake adds
// its own line after the "#?RADIANCE" one, which readers skip as an unknown variable.
constexpr const char* kHdrSoftwareKey = "SOFTWARE=";

void stamp_hdr(std::vector<unsigned char>& encoded) {
  const auto first_line_end = std::find(encoded.begin(), encoded.end(), '\n');
  if (first_line_end == encoded.end()) return;
  const std::string line = std::string(kHdrSoftwareKey) + kSoftware + "\n";
  encoded.insert(first_line_end + 1, line.begin(), line.end());
}

// The SOFTWARE= line of a Radiance file's header, "" when the file is not one.
std::string hdr_software(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  if (!std::getline(in, line) || line.rfind("#?", 0) != 0) return "";
  for (int i = 0; i < 64 && std::getline(in, line) && !line.empty(); ++i)
    if (line.rfind(kHdrSoftwareKey, 0) == 0) return line.substr(std::strlen(kHdrSoftwareKey));
  return "";
}

class OiioImagePlugin final : public ImagePlugin {
 public:
  OiioImagePlugin() {
    // Debian's build prints "OIIO DEBUG" lines to stderr; a command's stderr is its errors.
    OIIO::attribute("debug", 0);
  }

  std::string decode(const Source& source, int max_channels, uint64_t max_values,
                     Decoded& out) const override try {
    ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);  // alpha as stored, colour not premultiplied
    std::unique_ptr<OIIO::Filesystem::IOMemReader> memory;
    if (source.data) {
      // Given in the configuration, not as open's argument: OpenImageIO 2.4's open() probes the
      // format with the proxy, closes, and reopens without it.
      memory = std::make_unique<OIIO::Filesystem::IOMemReader>(source.data, source.size);
      const void* proxy = memory.get();
      config.attribute("oiio:ioproxy", TypeDesc::PTR, &proxy);
    }
    const std::unique_ptr<ImageInput> in = ImageInput::open(source.path, &config);
    if (!in) return one_line(OIIO::geterror(), "unknown image format");
    const ImageSpec& spec = in->spec();
    if (spec.depth > 1) return "volume images are not supported";
    if (std::string problem =
            size_problem(spec.width, spec.height, spec.nchannels, max_channels, max_values);
        !problem.empty())
      return problem;
    const int kept = std::min(spec.nchannels, max_channels);
    Image& image = out.image;
    image.width = spec.width;
    image.height = spec.height;
    image.channels = kept;
    image.pixels.assign(size_t(spec.width) * size_t(spec.height) * size_t(kept), 0.0f);
    if (!in->read_image(0, 0, 0, kept, TypeDesc::FLOAT, image.pixels.data()))
      return one_line(in->geterror(), "unreadable pixel data");
    out.display_encoded = !spec.format.is_floating_point();
    out.alpha_channel = spec.alpha_channel < kept ? spec.alpha_channel : -1;
    return "";
  } catch (const std::exception& error) {
    return one_line(error.what(), "decoding failed");
  }

  std::string encode(const std::string& format, const Pixels& pixels,
                     std::vector<unsigned char>& out) const override try {
    out.clear();
    OIIO::Filesystem::IOVecOutput memory(out);
    const std::unique_ptr<ImageOutput> writer = ImageOutput::create(format, &memory);
    if (!writer) return one_line(OIIO::geterror(), "unknown image format");
    const std::string name = writer->format_name();
    if (!writer->supports("ioproxy"))
      return "OpenImageIO cannot encode " + name + " files in memory; choose another format";
    const bool hdr = name == "hdr";
    std::vector<float> rgb;
    if (hdr && pixels.values && pixels.channels != 3) rgb = to_rgb(pixels);
    const int channels = rgb.empty() ? pixels.channels : 3;

    ImageSpec spec(pixels.width, pixels.height, channels, file_type(pixels.stored));
    spec.attribute("Software", kSoftware);
    spec.attribute("oiio:UnassociatedAlpha", 1);  // alpha as given, colour not divided by it
    // An int "DateTime" is one the EXR and TIFF writers skip; without one they record the
    // time of writing, and the same pixels would give different bytes (bake checksums).
    spec.attribute("DateTime", 0);
    if (name == "openexr") spec.attribute("compression", "zip");
    if (pixels.srgb) spec.attribute("oiio:ColorSpace", "sRGB");
    if (!writer->open(format, spec)) return one_line(writer->geterror(), "cannot open");
    const float* values = rgb.empty() ? pixels.values : rgb.data();
    const bool written = pixels.bytes ? writer->write_image(TypeDesc::UINT8, pixels.bytes)
                                      : writer->write_image(TypeDesc::FLOAT, values);
    const bool closed = writer->close();
    if (!written || !closed) return one_line(writer->geterror(), "encoding failed");
    if (hdr) stamp_hdr(out);
    return "";
  } catch (const std::exception& error) {
    return one_line(error.what(), "encoding failed");
  }

  std::string software(const std::string& path) const override try {
    if (std::string hdr = hdr_software(path); !hdr.empty()) return hdr;
    const std::unique_ptr<ImageInput> in = ImageInput::open(path);
    if (!in) {
      OIIO::geterror();  // clear the message OpenImageIO keeps for this thread
      return "";
    }
    return in->spec().get_string_attribute("Software");
  } catch (const std::exception&) {
    return "";
  }
};

}  // namespace

}  // namespace lb::codecs

extern "C" __attribute__((visibility("default"))) const lb::codecs::ImagePlugin*
lightbake_image_plugin(int version) {
  static const lb::codecs::OiioImagePlugin plugin;
  return version == lb::codecs::kImagePluginVersion ? &plugin : nullptr;
}
