// The image formats behind image_io.h (OpenImageIO, through lightbake_images.so): decoded values,
// files from other writers, the "written by lightbake" stamps, and memory against file decoding.

#include <gtest/gtest.h>
#include <png.h>
#include <stb/stb_image_write.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "bake/io/image_io.h"
#include "bake/io/scene_load.h"
#include "bake/io/textures.h"
#include "test_helpers.h"

namespace lb {
namespace {

std::string fresh_dir(const std::string& name) {
  return test::fresh_dir("image_codecs", name);
}

std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

void write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

// A 16-bit grey PNG written by libpng with no text chunk: another tool's file.
void write_foreign_png16(const std::string& path, const std::vector<uint16_t>& row) {
  std::FILE* file = std::fopen(path.c_str(), "wb");
  ASSERT_NE(file, nullptr);
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  png_init_io(png, file);
  png_set_IHDR(png, info, png_uint_32(row.size()), 1, 16, PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  std::vector<png_byte> big_endian;
  for (uint16_t v : row) big_endian.insert(big_endian.end(), {png_byte(v >> 8), png_byte(v)});
  png_write_row(png, big_endian.data());
  png_write_end(png, info);
  png_destroy_write_struct(&png, &info);
  std::fclose(file);
}

// A 2 x 1 palette PNG (libpng) whose first entry is half transparent: it decodes to RGBA.
void write_foreign_palette_png(const std::string& path) {
  std::FILE* file = std::fopen(path.c_str(), "wb");
  ASSERT_NE(file, nullptr);
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  png_init_io(png, file);
  png_set_IHDR(png, info, 2, 1, 8, PNG_COLOR_TYPE_PALETTE, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_color palette[2] = {{255, 0, 0}, {0, 51, 255}};
  png_set_PLTE(png, info, palette, 2);
  png_byte alpha[1] = {128};
  png_set_tRNS(png, info, alpha, 1, nullptr);
  png_write_info(png, info);
  png_byte row[2] = {0, 1};
  png_write_row(png, row);
  png_write_end(png, info);
  png_destroy_write_struct(&png, &info);
  std::fclose(file);
}

TEST(ImageCodecs, EightBitSamplesDecodeToTheirFraction) {
  // value * (1 / 255): the floats stb_image gave too, so textures bake to the same bits as before.
  const std::string dir = fresh_dir("eight_bit");
  std::vector<uint8_t> bytes(256);
  for (int i = 0; i < 256; ++i) bytes[size_t(i)] = uint8_t(i);
  write_png8(dir + "/ramp.png", 256, 1, 1, bytes);
  const Image back = read_image(dir + "/ramp.png");
  ASSERT_EQ(back.channels, 1);
  for (int i = 0; i < 256; ++i) EXPECT_EQ(back.pixels[size_t(i)], float(i) * (1.0f / 255.0f)) << i;
}

TEST(ImageCodecs, SixteenBitPngFromAnotherWriter) {
  const std::string dir = fresh_dir("sixteen_bit");
  std::vector<uint16_t> row;
  for (uint32_t v = 0; v <= 65535; v += 257 * 3) row.push_back(uint16_t(v));
  row.push_back(1);  // below one 8-bit step: only a 16-bit decode keeps it
  write_foreign_png16(dir + "/ramp16.png", row);
  const Image back = read_image(dir + "/ramp16.png");
  ASSERT_EQ(back.width, int(row.size()));
  for (size_t i = 0; i < row.size(); ++i)
    EXPECT_EQ(back.pixels[i], float(row[i]) * (1.0f / 65535.0f)) << i;
  EXPECT_FALSE(is_lightbake_image(dir + "/ramp16.png"));
}

TEST(ImageCodecs, OtherWritersFormatsDecode) {
  const std::string dir = fresh_dir("formats");
  write_foreign_palette_png(dir + "/palette.png");
  const Image palette = read_image(dir + "/palette.png");
  ASSERT_EQ(palette.channels, 4);
  EXPECT_EQ(palette.pixels, (std::vector<float>{1.0f, 0.0f, 0.0f, 128 * (1.0f / 255.0f), 0.0f,
                                                51 * (1.0f / 255.0f), 1.0f, 1.0f}));

  // Grey with alpha, RGB and RGBA through stb's own writers (TGA, BMP, JPEG).
  const std::vector<uint8_t> grey_alpha = {100, 50, 200, 255};
  ASSERT_TRUE(stbi_write_png((dir + "/ga.png").c_str(), 2, 1, 2, grey_alpha.data(), 4));
  const Image ga = read_image(dir + "/ga.png", ImageDecode::srgb_to_linear);
  ASSERT_EQ(ga.channels, 2);
  EXPECT_FLOAT_EQ(ga.pixels[0], srgb_eotf(100 * (1.0f / 255.0f)));
  EXPECT_EQ(ga.pixels[1], 50 * (1.0f / 255.0f));  // alpha stays linear
  const std::vector<uint8_t> rgba = {10, 200, 30, 40, 250, 0, 128, 255};
  ASSERT_TRUE(stbi_write_tga((dir + "/a.tga").c_str(), 2, 1, 4, rgba.data()));
  ASSERT_TRUE(stbi_write_bmp((dir + "/a.bmp").c_str(), 2, 1, 3, rgba.data()));
  ASSERT_TRUE(stbi_write_jpg((dir + "/a.jpg").c_str(), 2, 1, 4, rgba.data(), 100));
  const Image tga = read_image(dir + "/a.tga");
  ASSERT_EQ(tga.channels, 4);
  for (size_t i = 0; i < rgba.size(); ++i) EXPECT_EQ(tga.pixels[i], rgba[i] * (1.0f / 255.0f));
  const Image bmp = read_image(dir + "/a.bmp");
  ASSERT_EQ(bmp.channels, 3);
  for (size_t i = 0; i < 3; ++i) EXPECT_EQ(bmp.pixels[i], rgba[i] * (1.0f / 255.0f)) << i;
  const Image jpg = read_image(dir + "/a.jpg");  // lossy: within a few steps
  ASSERT_EQ(jpg.channels, 3);
  EXPECT_NEAR(jpg.pixels[1], 200 / 255.0f, 0.1f);
}

TEST(ImageCodecs, RgbeRoundTripKeepsItsPrecision) {
  const std::string dir = fresh_dir("rgbe");
  Image image(5, 3, 3);
  for (size_t i = 0; i < image.pixels.size(); ++i)
    image.pixels[i] = std::exp2(float(i % 7) * 3.0f - 9.0f) * (1.0f + 0.1f * float(i % 3));
  write_hdr(dir + "/a.hdr", image);
  const Image back = read_image(dir + "/a.hdr");
  ASSERT_EQ(back.width, 5);
  ASSERT_EQ(back.height, 3);
  ASSERT_EQ(back.channels, 3);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 5; ++x) {
      // 8-bit mantissas under the pixel's largest channel's exponent: within 1/128 of it.
      const float largest = std::max({image.at(x, y, 0), image.at(x, y, 1), image.at(x, y, 2)});
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(back.at(x, y, c), image.at(x, y, c), largest / 128.0f) << x << " " << y;
    }
}

TEST(ImageCodecs, StampsTellOurFilesFromOthers) {
  const std::string dir = fresh_dir("stamps");
  const Image image(4, 2, 3, 0.25f);
  write_png(dir + "/ours.png", image);
  write_exr(dir + "/ours.exr", image);
  write_hdr(dir + "/ours.hdr", image);
  for (const char* name : {"ours.png", "ours.exr", "ours.hdr"})
    EXPECT_TRUE(is_lightbake_image(dir + "/" + name)) << name;

  // Other writers: stb's PNG and RGBE, and our EXR with another name in its Software field.
  const std::vector<uint8_t> grey(8, 64);
  ASSERT_TRUE(stbi_write_png((dir + "/theirs.png").c_str(), 4, 2, 1, grey.data(), 4));
  ASSERT_TRUE(stbi_write_hdr((dir + "/theirs.hdr").c_str(), 4, 2, 3, image.pixels.data()));
  std::string exr = file_bytes(dir + "/ours.exr");
  const size_t stamp = exr.find("lightbake");
  ASSERT_NE(stamp, std::string::npos);
  exr.replace(stamp, 9, "otherbake");
  write_bytes(dir + "/theirs.exr", exr);
  EXPECT_EQ(read_image(dir + "/theirs.exr").pixels, read_image(dir + "/ours.exr").pixels);
  write_bytes(dir + "/garbage.exr", "not an image");
  for (const char* name : {"theirs.png", "theirs.hdr", "theirs.exr", "garbage.exr", "missing.png"})
    EXPECT_FALSE(is_lightbake_image(dir + "/" + name)) << name;
}

TEST(ImageCodecs, TexturesDecodeAlikeFromMemoryAndFile) {
  const std::string dir = fresh_dir("memory");
  Image image(6, 5, 4);
  for (size_t i = 0; i < image.pixels.size(); ++i) image.pixels[i] = float(i % 11) / 10.0f;
  write_png(dir + "/t.png", image);
  write_exr(dir + "/t.exr", image, ExrPixelType::float32);
  for (const char* name : {"t.png", "t.exr"}) {
    const std::string path = dir + "/" + name;
    const std::string bytes = file_bytes(path);
    const Texture from_file = load_texture_file(path, true, "test");
    const Texture from_memory = load_texture_memory(bytes.data(), bytes.size(), name, true, "test");
    EXPECT_EQ(from_file.channels, 4) << name;
    EXPECT_EQ(from_file.texels, from_memory.texels) << name;
    EXPECT_EQ(from_file.srgb_decoded, from_memory.srgb_decoded) << name;
  }
  // The EXR is linear and RGBA in that order (the file stores A, B, G, R).
  EXPECT_EQ(load_texture_file(dir + "/t.exr", true, "test").texels, image.pixels);
  // Cut short, the EXR fails with a reason instead of reading past its end.
  const std::string cut = file_bytes(dir + "/t.exr").substr(0, 200);
  EXPECT_THROW(load_texture_memory(cut.data(), cut.size(), "cut.exr", false, "test"), SceneError);
}

}  // namespace
}  // namespace lb
