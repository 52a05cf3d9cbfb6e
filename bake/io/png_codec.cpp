// PNG out through libpng, and the "Software" stamp read back (image_codecs.h). PNG pixels are
// decoded by stb (stb_codec.cpp), which reads every PNG libpng writes.
//
// libpng reports errors by longjmp to the setjmp in each function below, so those functions
// hold no object with a destructor between setjmp and the end of their libpng calls; the
// FILE and the libpng structures are released after the jump by plain code.

#include <png.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "bake/io/image_codecs.h"

namespace lb::codecs {

namespace {

constexpr int kColourTypes[4] = {PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA, PNG_COLOR_TYPE_RGB,
                                 PNG_COLOR_TYPE_RGB_ALPHA};

// libpng's message, kept for the exception thrown after the jump back.
struct ErrorText {
  char text[256] = "";
};

void on_error(png_structp png, png_const_charp message) {
  auto* error = static_cast<ErrorText*>(png_get_error_ptr(png));
  std::snprintf(error->text, sizeof error->text, "%s", message);
  png_longjmp(png, 1);
}

void on_warning(png_structp, png_const_charp) {}

// Returns false with `error` filled when libpng fails.
bool encode(std::FILE* file, int width, int height, int channels, const uint8_t* bytes,
            ErrorText* error) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, error, on_error, on_warning);
  if (!png) return false;
  png_infop info = png_create_info_struct(png);
  if (!info || setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return false;
  }
  png_init_io(png, file);
  png_set_IHDR(png, info, png_uint_32(width), png_uint_32(height), 8, kColourTypes[channels - 1],
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_sRGB_gAMA_and_cHRM(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
  png_text software{};
  software.compression = PNG_TEXT_COMPRESSION_NONE;
  software.key = const_cast<char*>("Software");
  software.text = const_cast<char*>(kSoftware);
  png_set_text(png, info, &software, 1);
  png_write_info(png, info);
  const size_t row_bytes = size_t(width) * size_t(channels);
  for (int y = 0; y < height; ++y) png_write_row(png, bytes + size_t(y) * row_bytes);
  png_write_end(png, info);
  png_destroy_write_struct(&png, &info);
  return true;
}

bool has_stamp(std::FILE* file) {
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, on_warning);
  if (!png) return false;
  ErrorText error;
  png_set_error_fn(png, &error, on_error, on_warning);
  png_infop info = png_create_info_struct(png);
  if (!info || setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    return false;
  }
  png_init_io(png, file);
  png_read_info(png, info);  // the text chunks before the pixel data
  png_textp texts = nullptr;
  int count = 0;
  png_get_text(png, info, &texts, &count);
  bool stamped = false;
  for (int i = 0; i < count; ++i)
    if (std::strcmp(texts[i].key, "Software") == 0 && std::strcmp(texts[i].text, kSoftware) == 0)
      stamped = true;
  png_destroy_read_struct(&png, &info, nullptr);
  return stamped;
}

}  // namespace

void write_png(const std::string& path, int width, int height, int channels,
               const uint8_t* bytes) {
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (!file) throw std::runtime_error(path + ": cannot write: " + std::strerror(errno));
  ErrorText error;
  const bool encoded = encode(file, width, height, channels, bytes, &error);
  const bool closed = std::fclose(file) == 0;
  if (!encoded) throw std::runtime_error(path + ": cannot write: " + error.text);
  if (!closed) throw std::runtime_error(path + ": cannot write: " + std::strerror(errno));
}

bool png_is_stamped(const std::string& path) {
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (!file) return false;
  const bool stamped = has_stamp(file);  // libpng checks the signature itself
  std::fclose(file);
  return stamped;
}

}  // namespace lb::codecs
