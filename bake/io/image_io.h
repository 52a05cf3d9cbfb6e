#pragma once
// Images in and out (every format OpenImageIO reads and writes, image_codecs.h), exposure and
// tone mapping from radiance to display, and the comparison metrics image tests use.
//
// Conventions
// - `Image` holds float pixels, row-major, top row first, `channels` floats per pixel.
// - Linear images hold radiance in W/(sr m^2) per linear-sRGB/Rec.709 channel (or any linear
//   quantity); EXR stores them as they are.
// - PNG is 8-bit sRGB-encoded. Writing a PNG therefore needs display values: either call
//   write_png() with linear values in [0,1] (clamped, then the sRGB OETF), or
//   write_png_tonemapped() with radiance and a ToneMap.
// - Tone mapping (one formula, used by the CLI, the HQ renderer and mirrored in the viewer's
//   shader):
//       x        = radiance * 2^exposure               (exposure in stops, per channel)
//       display  = curve(x)                            (linear display value in [0,1])
//       encoded  = srgb_oetf(display)                  (then * 255, rounded, for 8 bits)
//   curves:  clamp     curve(x) = min(max(x, 0), 1)
//            reinhard  curve(x) = x / (1 + x)
//            aces      curve(x) = clamp01(x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14))
//                      (Narkowicz's 2015 fit of the ACES RRT+ODT, applied per channel)
//   The DEFAULT is aces with exposure 0. Alpha (a 4th channel) is passed through clamped.
// All writes are atomic (encoded in memory, then temp file + rename, see atomic_file.h). Errors
// throw std::runtime_error with a message that starts with the path.

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace lb {

struct Image {
  int width = 0;
  int height = 0;
  int channels = 0;
  std::vector<float> pixels;  // row-major, top row first, `channels` floats per pixel

  Image() = default;
  Image(int width, int height, int channels, float fill = 0.0f);

  bool empty() const { return pixels.empty(); }
  size_t index(int x, int y, int c = 0) const {
    return (size_t(y) * size_t(width) + size_t(x)) * size_t(channels) + size_t(c);
  }
  float& at(int x, int y, int c = 0) { return pixels[index(x, y, c)]; }
  float at(int x, int y, int c = 0) const { return pixels[index(x, y, c)]; }
};

// ---- sRGB transfer functions (IEC 61966-2-1), per value ----------------------------------
float srgb_oetf(float linear);   // linear [0,1] -> encoded [0,1]; 0.5 -> 0.7354
float srgb_eotf(float encoded);  // encoded [0,1] -> linear [0,1]; inverse of srgb_oetf
// A [0,1] value as a byte: round(255 * value), clamped to [0,1] first.
uint8_t unit_to_byte(float unit);

// ---- Tone mapping -------------------------------------------------------------------------
enum class ToneCurve { clamp, reinhard, aces };
const char* to_string(ToneCurve curve);
// Parses "clamp", "reinhard", "aces"; throws std::invalid_argument otherwise.
ToneCurve parse_tone_curve(const std::string& name);

struct ToneMap {
  float exposure = 0.0f;  // stops: radiance is multiplied by 2^exposure
  ToneCurve curve = ToneCurve::aces;
};

// Linear display value in [0,1] for one radiance value (exposure and curve, no sRGB).
float tonemap_value(float radiance, const ToneMap& tone);
// 8-bit sRGB for one radiance value: round(255 * srgb_oetf(tonemap_value(radiance))).
uint8_t tonemap_to_srgb8(float radiance, const ToneMap& tone);
// The whole image as 8-bit sRGB bytes, same layout as `image.pixels`; alpha kept linear.
std::vector<uint8_t> tonemap_to_srgb8(const Image& radiance, const ToneMap& tone);

// ---- Writing (atomic) ---------------------------------------------------------------------
enum class ExrPixelType { half, float32 };
// A file's sample type. Integers store round(value * max) of values clamped to [0,1].
enum class SampleType { uint8, uint16, half, float32 };

// EXR with the image's channels (1: Y, 3: RGB, 4: RGBA), ZIP compressed.
void write_exr(const std::string& path, const Image& image, ExrPixelType type = ExrPixelType::half);
// Radiance RGBE (.hdr): RGB, 8-bit mantissas with a shared exponent (within 1/128 of a pixel's
// largest channel), linear values as given.
void write_hdr(const std::string& path, const Image& image);
// PNG from linear display values in [0,1]: clamped, sRGB OETF, 8 bits (1..4 channels).
void write_png(const std::string& path, const Image& linear_display);
// PNG from radiance: tone mapped as described above.
void write_png_tonemapped(const std::string& path, const Image& radiance, const ToneMap& tone = {});
// PNG from ready 8-bit bytes (already sRGB encoded), e.g. a framebuffer read-back.
// `bytes` is row-major, top row first, width*height*channels long.
void write_png8(const std::string& path, int width, int height, int channels,
                const std::vector<uint8_t>& bytes);
// Chooses by extension: .exr -> write_exr (half), .png -> write_png_tonemapped(default).
void write_image(const std::string& path, const Image& image);
// The values as they are (no tone curve, no sRGB encoding) in the format the extension names
// (.tif, .png, .exr, .webp, .jpg, ...; 1..4 channels), stored as `sample` where the format
// offers it: textures and data maps for other tools, e.g. a 16-bit TIFF height map.
void write_image_values(const std::string& path, const Image& image, SampleType sample);

// ---- Reading ------------------------------------------------------------------------------
enum class ImageDecode {
  as_stored,       // integer formats become value/max in [0,1]; floats unchanged (data maps)
  srgb_to_linear,  // integer formats: colour channels through srgb_eotf (colour textures);
                   // float formats (EXR, HDR) are already linear and stay unchanged
};
// True if `path` is an image this project wrote (stamped "Software: lightbake" by the writers
// above); false for anything else, unreadable files included.
bool is_lightbake_image(const std::string& path);

// Any format OpenImageIO reads (PNG, JPEG, OpenEXR, Radiance HDR, TIFF, .tx, DDS, WebP, TGA,
// BMP, PSD, GIF, PNM, ...); the first image at full resolution, at most 4 channels, at most
// limits::kMaxTextureValues values (checked before decoding).
Image read_image(const std::string& path, ImageDecode decode = ImageDecode::as_stored);
// Same, decoding `bytes` already read from `path` (named in messages): a caller that checked
// the bytes' hash decodes exactly what it checked.
Image read_image(const std::string& path, std::span<const std::byte> bytes,
                 ImageDecode decode = ImageDecode::as_stored);

// ---- Comparison (for tests) ---------------------------------------------------------------
struct ImageDifference {
  double rmse = 0.0;           // sqrt(mean over all values of (a - ref)^2)
  double mean_abs = 0.0;       // mean |a - ref| over all values
  double mean_relative = 0.0;  // mean |a - ref| / (|ref| + relative_epsilon)
  double max_abs = 0.0;        // largest |a - ref|
  int max_x = 0, max_y = 0;    // where max_abs occurs
  double fraction_over = 0.0;  // fraction of pixels with any channel |a - ref| > threshold
  size_t pixels = 0;
};
// Throws std::invalid_argument when the sizes or channel counts differ.
ImageDifference compare_images(const Image& image, const Image& reference, float threshold = 0.01f,
                               float relative_epsilon = 1e-3f);
// Per-value |image - reference|.
Image absolute_difference(const Image& image, const Image& reference);

// Leaves evidence of a failed image test in `directory` (created if missing):
//   NAME.exr, NAME_ref.exr, NAME_diff.exr   (float, the values compared)
//   NAME.png, NAME_ref.png                  (tone mapped with the default ToneMap)
//   NAME_diff.png                           (|difference| scaled so the largest is white)
// Returns the path prefix DIRECTORY/NAME.
std::string write_comparison(const std::string& directory, const std::string& name,
                             const Image& image, const Image& reference);

}  // namespace lb
