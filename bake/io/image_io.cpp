#include "bake/io/image_io.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <stdexcept>

#include "bake/io/atomic_file.h"
#include "bake/io/image_codecs.h"
#include "bake/input_file.h"
#include "bake/io/input_limits.h"

namespace lb {

namespace {

namespace fs = std::filesystem;

void check_shape(const std::string& path, int width, int height, int channels, size_t values) {
  if (width <= 0 || height <= 0 || channels < 1 || channels > 4)
    throw std::runtime_error(path + ": cannot write a " + std::to_string(width) + "x" +
                             std::to_string(height) + "x" + std::to_string(channels) + " image");
  if (values != size_t(width) * size_t(height) * size_t(channels))
    throw std::runtime_error(path + ": pixel buffer holds " + std::to_string(values) +
                             " values, expected width*height*channels");
}

float clamp01(float x) {
  return std::min(std::max(x, 0.0f), 1.0f);
}

bool is_alpha(int channel, int channels) {
  return channels == 4 && channel == 3;
}

}  // namespace

Image::Image(int width, int height, int channels, float fill)
    : width(width),
      height(height),
      channels(channels),
      pixels(
          size_t(std::max(width, 0)) * size_t(std::max(height, 0)) * size_t(std::max(channels, 0)),
          fill) {}

bool is_lightbake_image(const std::string& path) {
  return codecs::is_stamped(path);
}

// ---- sRGB --------------------------------------------------------------------------------

float srgb_oetf(float linear) {
  const float x = clamp01(linear);
  return x <= 0.0031308f ? 12.92f * x : 1.055f * std::pow(x, 1.0f / 2.4f) - 0.055f;
}

float srgb_eotf(float encoded) {
  const float x = clamp01(encoded);
  return x <= 0.04045f ? x / 12.92f : std::pow((x + 0.055f) / 1.055f, 2.4f);
}

uint8_t unit_to_byte(float unit) {
  return uint8_t(std::lround(clamp01(unit) * 255.0f));
}

// ---- Tone mapping ------------------------------------------------------------------------

const char* to_string(ToneCurve curve) {
  switch (curve) {
    case ToneCurve::clamp:
      return "clamp";
    case ToneCurve::reinhard:
      return "reinhard";
    case ToneCurve::aces:
      return "aces";
  }
  return "?";
}

ToneCurve parse_tone_curve(const std::string& name) {
  if (name == "clamp") return ToneCurve::clamp;
  if (name == "reinhard") return ToneCurve::reinhard;
  if (name == "aces") return ToneCurve::aces;
  throw std::invalid_argument("unknown tone curve '" + name +
                              "' (expected clamp, reinhard or aces)");
}

float tonemap_value(float radiance, const ToneMap& tone) {
  // NaN radiance maps to black rather than poisoning a whole PNG.
  const float x = std::isnan(radiance) ? 0.0f : std::max(radiance, 0.0f) * std::exp2(tone.exposure);
  switch (tone.curve) {
    case ToneCurve::clamp:
      return clamp01(x);
    case ToneCurve::reinhard:
      return std::isinf(x) ? 1.0f : x / (1.0f + x);
    case ToneCurve::aces:
      if (std::isinf(x)) return 1.0f;
      return clamp01(x * (2.51f * x + 0.03f) / (x * (2.43f * x + 0.59f) + 0.14f));
  }
  return 0.0f;
}

uint8_t tonemap_to_srgb8(float radiance, const ToneMap& tone) {
  return unit_to_byte(srgb_oetf(tonemap_value(radiance, tone)));
}

std::vector<uint8_t> tonemap_to_srgb8(const Image& radiance, const ToneMap& tone) {
  std::vector<uint8_t> bytes(radiance.pixels.size());
  const size_t channels = size_t(std::max(radiance.channels, 1));
  for (size_t i = 0; i < bytes.size(); ++i) {
    const float value = radiance.pixels[i];
    bytes[i] = is_alpha(int(i % channels), radiance.channels) ? unit_to_byte(value)
                                                              : tonemap_to_srgb8(value, tone);
  }
  return bytes;
}

// ---- Writing -----------------------------------------------------------------------------

namespace {

// Encodes (stamped as ours, so a later run may replace the file: written_by_lightbake) and
// writes atomically; `format` as codecs::encode takes it.
void write_encoded(const std::string& path, const std::string& format,
                   const codecs::Pixels& pixels) {
  std::vector<unsigned char> bytes;
  try {
    bytes = codecs::encode(format, pixels);
  } catch (const std::exception& error) {
    throw std::runtime_error(path + ": cannot write: " + error.what());
  }
  write_file_atomic(path, std::as_bytes(std::span(bytes)));
}

codecs::Pixels float_pixels(const std::string& path, const Image& image, SampleType stored) {
  check_shape(path, image.width, image.height, image.channels, image.pixels.size());
  return {.width = image.width, .height = image.height, .channels = image.channels,
          .values = image.pixels.data(), .stored = stored};
}

}  // namespace

void write_exr(const std::string& path, const Image& image, ExrPixelType type) {
  const SampleType stored = type == ExrPixelType::half ? SampleType::half : SampleType::float32;
  write_encoded(path, "openexr", float_pixels(path, image, stored));
}

void write_hdr(const std::string& path, const Image& image) {
  write_encoded(path, "hdr", float_pixels(path, image, SampleType::float32));
}

void write_image_values(const std::string& path, const Image& image, SampleType sample) {
  write_encoded(path, path, float_pixels(path, image, sample));
}

void write_png8(const std::string& path, int width, int height, int channels,
                const std::vector<uint8_t>& bytes) {
  check_shape(path, width, height, channels, bytes.size());
  write_encoded(path, "png",
                {.width = width, .height = height, .channels = channels, .bytes = bytes.data(),
                 .stored = SampleType::uint8, .srgb = true});
}

void write_png(const std::string& path, const Image& linear_display) {
  std::vector<uint8_t> bytes(linear_display.pixels.size());
  for (size_t i = 0; i < bytes.size(); ++i) {
    const float value = linear_display.pixels[i];
    const bool alpha =
        is_alpha(int(i % size_t(std::max(linear_display.channels, 1))), linear_display.channels);
    bytes[i] = unit_to_byte(alpha ? value : srgb_oetf(std::isnan(value) ? 0.0f : value));
  }
  write_png8(path, linear_display.width, linear_display.height, linear_display.channels, bytes);
}

void write_png_tonemapped(const std::string& path, const Image& radiance, const ToneMap& tone) {
  write_png8(path, radiance.width, radiance.height, radiance.channels,
             tonemap_to_srgb8(radiance, tone));
}

void write_image(const std::string& path, const Image& image) {
  const std::string extension = lowercase_extension(path);
  if (extension == ".exr") return write_exr(path, image);
  if (extension == ".png") return write_png_tonemapped(path, image);
  throw std::runtime_error(path + ": cannot write images of type '" + extension +
                           "' (expected .exr or .png)");
}

// ---- Reading -----------------------------------------------------------------------------

namespace {

Image decode_image(const codecs::Source& source, ImageDecode decode) {
  codecs::Decoded decoded;
  try {
    decoded = codecs::decode(source, 4, limits::kMaxTextureValues);
  } catch (const codecs::CodecError& error) {
    std::string reason = error.what();
    std::replace(reason.begin(), reason.end(), '\n', ' ');  // errors are one line
    throw std::runtime_error(source.path + ": cannot read image: " + reason);
  }
  Image& image = decoded.image;
  if (decode == ImageDecode::srgb_to_linear && decoded.display_encoded) {
    for (size_t i = 0; i < image.pixels.size(); ++i) {
      const int channel = int(i % size_t(image.channels));
      if (channel != decoded.alpha_channel) image.pixels[i] = srgb_eotf(image.pixels[i]);
    }
  }
  return std::move(image);
}

}  // namespace

Image read_image(const std::string& path, ImageDecode decode) {
  if (const std::string problem = input_file_problem(path); !problem.empty())
    throw std::runtime_error(path + ": cannot read image: " + problem);
  return decode_image({path}, decode);
}

Image read_image(const std::string& path, std::span<const std::byte> bytes, ImageDecode decode) {
  return decode_image({path, bytes.data(), bytes.size()}, decode);
}

// ---- Comparison --------------------------------------------------------------------------

static void require_same_shape(const Image& image, const Image& reference) {
  if (image.width != reference.width || image.height != reference.height ||
      image.channels != reference.channels || image.pixels.size() != reference.pixels.size())
    throw std::invalid_argument(
        "cannot compare a " + std::to_string(image.width) + "x" + std::to_string(image.height) +
        "x" + std::to_string(image.channels) + " image with a " + std::to_string(reference.width) +
        "x" + std::to_string(reference.height) + "x" + std::to_string(reference.channels) +
        " reference");
}

ImageDifference compare_images(const Image& image, const Image& reference, float threshold,
                               float relative_epsilon) {
  require_same_shape(image, reference);
  ImageDifference result;
  result.pixels = size_t(image.width) * size_t(image.height);
  if (result.pixels == 0) return result;
  double sum_squared = 0.0, sum_abs = 0.0, sum_relative = 0.0;
  size_t pixels_over = 0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      bool over = false;
      for (int c = 0; c < image.channels; ++c) {
        const double a = image.at(x, y, c), r = reference.at(x, y, c);
        const double difference = std::abs(a - r);
        sum_squared += difference * difference;
        sum_abs += difference;
        sum_relative += difference / (std::abs(r) + relative_epsilon);
        // `!(<=)` also counts NaN as a failure, and as the worst pixel.
        if (!(difference <= result.max_abs)) {
          result.max_abs = std::isnan(difference) ? INFINITY : difference;
          result.max_x = x;
          result.max_y = y;
        }
        if (!(difference <= threshold)) over = true;
      }
      if (over) ++pixels_over;
    }
  }
  const double values = double(image.pixels.size());
  result.rmse = std::sqrt(sum_squared / values);
  result.mean_abs = sum_abs / values;
  result.mean_relative = sum_relative / values;
  result.fraction_over = double(pixels_over) / double(result.pixels);
  return result;
}

Image absolute_difference(const Image& image, const Image& reference) {
  require_same_shape(image, reference);
  Image difference(image.width, image.height, image.channels);
  for (size_t i = 0; i < image.pixels.size(); ++i)
    difference.pixels[i] = std::abs(image.pixels[i] - reference.pixels[i]);
  return difference;
}

std::string write_comparison(const std::string& directory, const std::string& name,
                             const Image& image, const Image& reference) {
  std::error_code ec;
  fs::create_directories(directory, ec);
  if (ec) throw std::runtime_error(directory + ": cannot create directory: " + ec.message());
  const std::string prefix = (fs::path(directory) / name).string();
  write_exr(prefix + ".exr", image, ExrPixelType::float32);
  write_exr(prefix + "_ref.exr", reference, ExrPixelType::float32);
  write_png_tonemapped(prefix + ".png", image);
  write_png_tonemapped(prefix + "_ref.png", reference);
  if (image.width == reference.width && image.height == reference.height &&
      image.channels == reference.channels) {
    Image difference = absolute_difference(image, reference);
    write_exr(prefix + "_diff.exr", difference, ExrPixelType::float32);
    float largest = 0.0f;
    for (float v : difference.pixels)
      if (std::isfinite(v)) largest = std::max(largest, v);
    for (float& v : difference.pixels) v = largest > 0.0f ? v / largest : 0.0f;
    write_png(prefix + "_diff.png", difference);
  }
  return prefix;
}

}  // namespace lb
