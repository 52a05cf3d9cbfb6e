// Formats artists' tools write that the image layer reads through OpenImageIO (image_codecs.h):
// TIFF of 8, 16 and 32 bits, mipmapped .tx, DDS, WebP; their failures; and a scene textured from
// TIFF files rendering exactly as the same scene textured from PNG files.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "bake/io/image_io.h"
#include "bake/io/scene_load.h"
#include "bake/io/textures.h"
#include "test_helpers.h"

namespace lb {
namespace {

namespace fs = std::filesystem;

// An RGB image whose values are whole 8-bit steps k / 255 (stored exactly as k).
Image eight_bit_colours(int width, int height) {
  Image image(width, height, 3);
  for (size_t i = 0; i < image.pixels.size(); ++i)
    image.pixels[i] = float((i * 37 + 11) % 256) / 255.0f;
  return image;
}

// A height map of whole 16-bit steps k / 65535, most of them between two 8-bit steps.
Image sixteen_bit_heights(int width, int height) {
  Image image(width, height, 1);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) image.at(x, y) = float(x * 4099 + y * 257) / 65535.0f;
  return image;
}

std::string write_bytes(const fs::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
  return path.string();
}

std::string load_error(const std::string& path) {
  try {
    load_texture_file(path, true, "scene.toml:3:1: materials.wall.texture");
  } catch (const SceneError& error) {
    return error.what();
  }
  return "";
}

TEST(ImageFormats, TiffColourTextureLoadsTheTexelsWritten) {
  const fs::path dir = test::fresh_dir("image_formats", "tiff_colour");
  const Image colours = eight_bit_colours(5, 3);
  write_image_values((dir / "wall.tif").string(), colours, SampleType::uint8);
  write_image_values((dir / "wall.png").string(), colours, SampleType::uint8);

  const Texture data = load_texture_file((dir / "wall.tif").string(), false, "test");
  ASSERT_EQ(data.width, 5);
  ASSERT_EQ(data.height, 3);
  ASSERT_EQ(data.channels, 3);
  for (size_t i = 0; i < colours.pixels.size(); ++i)
    EXPECT_EQ(data.texels[i], std::round(colours.pixels[i] * 255.0f) * (1.0f / 255.0f)) << i;

  // As a colour texture: sRGB-decoded, texel for texel what the PNG gives.
  const Texture tiff = load_texture_file((dir / "wall.tif").string(), true, "test");
  const Texture png = load_texture_file((dir / "wall.png").string(), true, "test");
  EXPECT_TRUE(tiff.srgb_decoded);
  EXPECT_EQ(tiff.texels, png.texels);
  EXPECT_FLOAT_EQ(tiff.texels[4], srgb_eotf(data.texels[4]));
}

TEST(ImageFormats, SixteenAndThirtyTwoBitTiffKeepTheirPrecision) {
  const fs::path dir = test::fresh_dir("image_formats", "tiff_depths");
  const Image heights = sixteen_bit_heights(16, 4);
  write_image_values((dir / "height16.tif").string(), heights, SampleType::uint16);
  const Image sixteen = read_image((dir / "height16.tif").string());
  ASSERT_EQ(sixteen.channels, 1);
  for (size_t i = 0; i < heights.pixels.size(); ++i)
    EXPECT_EQ(sixteen.pixels[i], std::round(heights.pixels[i] * 65535.0f) * (1.0f / 65535.0f))
        << i;
  // 16 bits resolve steps 8 bits cannot: the loaded map has as many levels as the written one.
  std::vector<float> levels = sixteen.pixels;
  std::sort(levels.begin(), levels.end());
  EXPECT_EQ(std::unique(levels.begin(), levels.end()) - levels.begin(), 64);

  // Floats are stored and read as they are, and taken as linear (no sRGB decoding).
  Image radiance(3, 2, 3);
  for (size_t i = 0; i < radiance.pixels.size(); ++i) radiance.pixels[i] = 0.1f * float(i) + 3.5f;
  write_image_values((dir / "float.tif").string(), radiance, SampleType::float32);
  const Texture linear = load_texture_file((dir / "float.tif").string(), true, "test");
  EXPECT_FALSE(linear.srgb_decoded);
  EXPECT_EQ(linear.texels, radiance.pixels);
}

TEST(ImageFormats, MipmappedTxLoadsItsFullResolutionLevel) {
  ASSERT_EQ(test::run_command("maketx --help").status, 0) << "maketx missing: scripts/setup.sh";
  const fs::path dir = test::fresh_dir("image_formats", "tx");
  const Image colours = eight_bit_colours(16, 8);
  write_image_values((dir / "wall.tif").string(), colours, SampleType::uint8);
  const test::CliRun made = test::run_command("maketx wall.tif -o wall.tx", dir.string());
  ASSERT_EQ(made.status, 0) << made.err;
  const Texture tx = load_texture_file((dir / "wall.tx").string(), true, "test");
  const Texture tiff = load_texture_file((dir / "wall.tif").string(), true, "test");
  EXPECT_EQ(tx.width, 16);
  EXPECT_EQ(tx.height, 8);
  EXPECT_EQ(tx.texels, tiff.texels);
}

// An uncompressed 32-bit DDS (the DirectDraw Surface header: 4-byte magic, 124-byte header with
// its pixel format masks), as texture tools write for games: B, G, R, A bytes per texel.
std::string dds_bgra(int width, int height, const std::vector<uint8_t>& bgra) {
  std::string out = "DDS ";
  const auto u32 = [&](uint32_t v) {
    for (int shift = 0; shift < 32; shift += 8) out.push_back(char((v >> shift) & 0xff));
  };
  u32(124);                             // header size
  u32(0x1 | 0x2 | 0x4 | 0x8 | 0x1000);  // caps, height, width, pitch, pixel format
  u32(uint32_t(height));
  u32(uint32_t(width));
  u32(uint32_t(width) * 4);  // pitch
  u32(0);                    // depth
  u32(0);                    // mipmap count
  for (int i = 0; i < 11; ++i) u32(0);
  u32(32);          // pixel format size
  u32(0x40 | 0x1);  // RGB with alpha
  u32(0);           // no FourCC
  u32(32);          // bits per texel
  u32(0x00ff0000);  // R
  u32(0x0000ff00);  // G
  u32(0x000000ff);  // B
  u32(0xff000000);  // A
  u32(0x1000);      // caps: texture
  for (int i = 0; i < 4; ++i) u32(0);
  out.append(reinterpret_cast<const char*>(bgra.data()), bgra.size());
  return out;
}

TEST(ImageFormats, UncompressedDdsDecodes) {
  const fs::path dir = test::fresh_dir("image_formats", "dds");
  const std::vector<uint8_t> bgra = {10, 20, 30, 255, 200, 100, 50, 255,
                                     0,  0,  255, 255, 255, 255, 255, 255};
  const Image image = read_image(write_bytes(dir / "t.dds", dds_bgra(2, 2, bgra)));
  ASSERT_EQ(image.width, 2);
  ASSERT_EQ(image.height, 2);
  ASSERT_EQ(image.channels, 4);
  for (size_t texel = 0; texel < 4; ++texel)
    for (size_t c = 0; c < 3; ++c)
      EXPECT_EQ(image.pixels[texel * 4 + c], bgra[texel * 4 + 2 - c] * (1.0f / 255.0f))
          << texel << " " << c;
}

TEST(ImageFormats, WebpRoundTripsWithinItsCompression) {
  const fs::path dir = test::fresh_dir("image_formats", "webp");
  Image smooth(32, 16, 3);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 32; ++x) {
      smooth.at(x, y, 0) = float(x) / 31.0f;
      smooth.at(x, y, 1) = float(y) / 15.0f;
      smooth.at(x, y, 2) = 0.5f;
    }
  write_image_values((dir / "t.webp").string(), smooth, SampleType::uint8);
  const Image back = read_image((dir / "t.webp").string());
  ASSERT_EQ(back.width, 32);
  ASSERT_EQ(back.channels, 3);
  // Lossy (OpenImageIO 2.4 writes WebP at quality 100): the mean error stays within 2 steps.
  EXPECT_LT(compare_images(back, smooth).mean_abs, 2.0 / 255.0);
}

TEST(ImageFormats, BrokenFilesFailInOneLineNamingTheFile) {
  const fs::path dir = test::fresh_dir("image_formats", "broken");
  write_image_values((dir / "good.tif").string(), eight_bit_colours(64, 64), SampleType::uint8);
  const std::string good = test::read_bytes((dir / "good.tif").string());
  const std::string cut = write_bytes(dir / "cut.tif", good.substr(0, good.size() / 3));
  const std::string junk = write_bytes(dir / "junk.tif", "II*\0 not really a TIFF");
  for (const std::string& path : {cut, junk, (dir / "missing.tif").string()}) {
    const std::string message = load_error(path);
    EXPECT_NE(message.find("materials.wall.texture"), std::string::npos) << message;
    EXPECT_NE(message.find(path), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    try {
      read_image(path);
      ADD_FAILURE() << path << " read";
    } catch (const std::runtime_error& error) {
      EXPECT_EQ(std::string(error.what()).rfind(path + ": cannot read image: ", 0), 0u)
          << error.what();
      EXPECT_EQ(std::string(error.what()).find('\n'), std::string::npos) << error.what();
    }
  }
  // An extension OpenImageIO writes no format for is refused, naming the file; nothing is left.
  EXPECT_THROW(write_image_values((dir / "t.nosuchformat").string(), eight_bit_colours(2, 2),
                                  SampleType::uint8),
               std::runtime_error);
  EXPECT_FALSE(fs::exists(dir / "t.nosuchformat"));
}

// The Cornell box with its white material textured (colour) and bumped (16-bit height), the
// files written as PNG or as TIFF; direct light only, through the viewer's renderer.
Image textured_box_snapshot(const fs::path& dir, const std::string& extension) {
  std::ifstream in(test::source_dir() + "/scenes/cornell_box.toml");
  std::string scene((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string white = "white = { reflectance = [0.885809, 0.698859, 0.666422] }";
  const size_t at = scene.find(white);
  EXPECT_NE(at, std::string::npos);
  if (!extension.empty())
    scene.replace(at, white.size(),
                  "white = { texture = 'colour" + extension + "', bump = { height = 'height" +
                      extension + "', scale = 0.05 } }");
  const std::string name = "box" + extension;
  std::ofstream(dir / (name + ".toml")) << scene;
  const test::CliRun run = test::run_lightbake(
      "snapshot -q --no-bake --terms direct --size 160x120 " + name + ".toml -o " + name + ".exr",
      dir.string());
  EXPECT_EQ(run.status, 0) << run.err;
  return read_image((dir / (name + ".exr")).string());
}

TEST(ImageFormats, TiffTexturedSceneRendersAsThePngTexturedOne) {
  const fs::path dir = test::fresh_dir("image_formats", "scene");
  Image colour(8, 8, 3);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x)
      for (int c = 0; c < 3; ++c)
        colour.at(x, y, c) = ((x + y) % 2 ? std::vector{255, 64, 16} : std::vector{32, 128, 255})
                                 [size_t(c)] / 255.0f;
  const Image heights = sixteen_bit_heights(16, 16);
  for (const char* extension : {".png", ".tif"}) {
    write_image_values((dir / ("colour" + std::string(extension))).string(), colour,
                       SampleType::uint8);
    write_image_values((dir / ("height" + std::string(extension))).string(), heights,
                       SampleType::uint16);
  }
  const Image from_png = textured_box_snapshot(dir, ".png");
  const Image from_tiff = textured_box_snapshot(dir, ".tif");
  const Image plain = textured_box_snapshot(dir, "");
  ASSERT_FALSE(from_png.empty());
  const std::vector<Texture> png = load_scene((dir / "box.png.toml").string()).scene.textures;
  const std::vector<Texture> tiff = load_scene((dir / "box.tif.toml").string()).scene.textures;
  ASSERT_EQ(png.size(), 2u);
  ASSERT_EQ(tiff.size(), 2u);
  for (size_t t = 0; t < 2; ++t) EXPECT_TRUE(test::same_bits(tiff[t].texels, png[t].texels)) << t;
  EXPECT_TRUE(test::same_bits(from_tiff.pixels, from_png.pixels));
  // The textures do show: the plain box differs from the textured one.
  EXPECT_GT(compare_images(plain, from_png).mean_abs, 0.01);
}

}  // namespace
}  // namespace lb
