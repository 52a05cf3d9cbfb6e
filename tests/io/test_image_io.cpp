// Image I/O, tone mapping, comparison metrics and atomic writes.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "bake/io/atomic_file.h"
#include "bake/io/image_io.h"
#include "test_helpers.h"

namespace lb {
namespace {

namespace fs = std::filesystem;

// A fresh, empty directory under the test output directory.
std::string fresh_dir(const std::string& name) {
  return test::fresh_dir("image_io", name);
}

std::vector<std::string> entries(const std::string& dir) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) names.push_back(entry.path().filename());
  std::sort(names.begin(), names.end());
  return names;
}

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// A gradient with values that are exact in half precision: k/64 in [0, 4).
Image half_exact_image(int width, int height, int channels) {
  Image image(width, height, channels);
  for (size_t i = 0; i < image.pixels.size(); ++i) image.pixels[i] = float(i % 256) / 64.0f;
  return image;
}

// ---- sRGB and tone mapping -----------------------------------------------------------------

TEST(ToneMap, SrgbTransferKnownValues) {
  EXPECT_FLOAT_EQ(srgb_oetf(0.0f), 0.0f);
  EXPECT_FLOAT_EQ(srgb_oetf(1.0f), 1.0f);
  EXPECT_NEAR(srgb_oetf(0.5f), 0.735357f, 1e-5f);
  EXPECT_NEAR(srgb_oetf(0.002f), 12.92f * 0.002f, 1e-7f);  // linear segment
  EXPECT_NEAR(srgb_eotf(0.735357f), 0.5f, 1e-5f);
  for (float x = 0.0f; x <= 1.0f; x += 1.0f / 64.0f) EXPECT_NEAR(srgb_eotf(srgb_oetf(x)), x, 1e-6f);
}

TEST(ToneMap, ClampCurveIsLinearThenSrgb) {
  const ToneMap clamp{0.0f, ToneCurve::clamp};
  EXPECT_EQ(tonemap_to_srgb8(0.0f, clamp), 0);
  EXPECT_EQ(tonemap_to_srgb8(-3.0f, clamp), 0);
  EXPECT_EQ(tonemap_to_srgb8(0.5f, clamp), 188);  // round(255 * 0.73536) = 188
  EXPECT_EQ(tonemap_to_srgb8(1.0f, clamp), 255);
  EXPECT_EQ(tonemap_to_srgb8(7.0f, clamp), 255);
  // Exposure in stops: 0.125 * 2^2 = 0.5.
  EXPECT_FLOAT_EQ(tonemap_value(0.125f, {2.0f, ToneCurve::clamp}), 0.5f);
  EXPECT_FLOAT_EQ(tonemap_value(2.0f, {-2.0f, ToneCurve::clamp}), 0.5f);
  EXPECT_EQ(tonemap_to_srgb8(NAN, clamp), 0);
}

TEST(ToneMap, FilmicCurvesKnownValues) {
  const ToneMap reinhard{0.0f, ToneCurve::reinhard};
  EXPECT_FLOAT_EQ(tonemap_value(0.0f, reinhard), 0.0f);
  EXPECT_FLOAT_EQ(tonemap_value(1.0f, reinhard), 0.5f);
  EXPECT_FLOAT_EQ(tonemap_value(3.0f, reinhard), 0.75f);
  EXPECT_FLOAT_EQ(tonemap_value(INFINITY, reinhard), 1.0f);
  const ToneMap aces{};  // the default
  EXPECT_EQ(aces.curve, ToneCurve::aces);
  EXPECT_FLOAT_EQ(tonemap_value(0.0f, aces), 0.0f);
  // x(2.51x+0.03)/(x(2.43x+0.59)+0.14) at x = 1: 2.54 / 3.16.
  EXPECT_NEAR(tonemap_value(1.0f, aces), 2.54f / 3.16f, 1e-6f);
  EXPECT_FLOAT_EQ(tonemap_value(1000.0f, aces), 1.0f);
  // Monotonic over a wide range.
  float previous = 0.0f;
  for (float x = 0.001f; x < 100.0f; x *= 1.1f) {
    const float y = tonemap_value(x, aces);
    EXPECT_GE(y, previous) << x;
    previous = y;
  }
  EXPECT_EQ(parse_tone_curve("reinhard"), ToneCurve::reinhard);
  EXPECT_THROW(parse_tone_curve("filmic"), std::invalid_argument);
}

// Three bands (clamp, reinhard, aces) of radiance 0..4 left to right, written for a look and
// read back: each band rises monotonically and clamp saturates at radiance 1 (a quarter across).
TEST(ToneMap, RampPngPerCurve) {
  const std::string dir = fresh_dir("ramp");
  const int width = 256, band = 32;
  const ToneCurve curves[] = {ToneCurve::clamp, ToneCurve::reinhard, ToneCurve::aces};
  Image display(width, 3 * band, 3);
  for (int b = 0; b < 3; ++b)
    for (int y = b * band; y < (b + 1) * band; ++y)
      for (int x = 0; x < width; ++x)
        for (int c = 0; c < 3; ++c)
          display.at(x, y, c) =
              tonemap_value(4.0f * float(x) / float(width - 1), {0.0f, curves[b]});
  write_png(dir + "/ramp.png", display);
  const Image back = read_image(dir + "/ramp.png");
  for (int b = 0; b < 3; ++b) {
    const int y = b * band + band / 2;
    for (int x = 1; x < width; ++x) EXPECT_GE(back.at(x, y), back.at(x - 1, y)) << b << " " << x;
    EXPECT_EQ(back.at(0, y), 0.0f);
  }
  EXPECT_EQ(back.at(64, band / 2), 1.0f);                // clamp: radiance 1.004 is white
  EXPECT_LT(back.at(width - 1, band + band / 2), 1.0f);  // reinhard never reaches white: 0.8
  EXPECT_NEAR(back.at(width - 1, band + band / 2), srgb_oetf(0.8f), 1.0f / 255.0f);
}

// ---- Round trips -----------------------------------------------------------------------------

TEST(ImageIo, ExrFloatRoundTripIsExact) {
  const std::string dir = fresh_dir("exr_float");
  Image image(7, 5, 3);
  for (size_t i = 0; i < image.pixels.size(); ++i)
    image.pixels[i] = std::sin(float(i)) * 1000.0f + 1e-3f * float(i);
  write_exr(dir + "/a.exr", image, ExrPixelType::float32);
  const Image back = read_image(dir + "/a.exr");
  ASSERT_EQ(back.width, 7);
  ASSERT_EQ(back.height, 5);
  ASSERT_EQ(back.channels, 3);
  EXPECT_EQ(back.pixels, image.pixels);
  EXPECT_EQ(entries(dir), std::vector<std::string>{"a.exr"});  // no temporary left
}

TEST(ImageIo, ExrHalfRoundTripIsExactForHalfValues) {
  const std::string dir = fresh_dir("exr_half");
  for (int channels : {1, 3, 4}) {
    const Image image = half_exact_image(9, 4, channels);
    const std::string path = dir + "/c" + std::to_string(channels) + ".exr";
    write_exr(path, image);
    const Image back = read_image(path);
    ASSERT_EQ(back.channels, channels);
    EXPECT_EQ(back.pixels, image.pixels) << channels;
  }
  // Top row first: the first value written is the top-left pixel.
  Image marker(2, 2, 1, 0.0f);
  marker.at(1, 0) = 1.0f;
  write_exr(dir + "/marker.exr", marker);
  EXPECT_EQ(read_image(dir + "/marker.exr").at(1, 0), 1.0f);
}

TEST(ImageIo, PngRoundTripWithinOneStepAfterSrgb) {
  const std::string dir = fresh_dir("png");
  Image image(16, 8, 3);
  for (size_t i = 0; i < image.pixels.size(); ++i) image.pixels[i] = float(i % 97) / 96.0f;
  write_png(dir + "/a.png", image);

  const Image encoded = read_image(dir + "/a.png");  // as stored: sRGB values in [0,1]
  const Image linear = read_image(dir + "/a.png", ImageDecode::srgb_to_linear);
  ASSERT_EQ(encoded.width, 16);
  ASSERT_EQ(encoded.channels, 3);
  for (size_t i = 0; i < image.pixels.size(); ++i) {
    // Quantisation to 8 bits is half a step; allow one full step.
    EXPECT_NEAR(encoded.pixels[i], srgb_oetf(image.pixels[i]), 1.0f / 255.0f) << i;
    EXPECT_NEAR(srgb_oetf(linear.pixels[i]), srgb_oetf(image.pixels[i]), 1.0f / 255.0f) << i;
  }
  EXPECT_EQ(entries(dir), std::vector<std::string>{"a.png"});
}

TEST(ImageIo, PngAlphaIsStraightAndLinear) {
  const std::string dir = fresh_dir("png_alpha");
  Image image(2, 1, 4);
  image.pixels = {1.0f, 0.5f, 0.0f, 0.5f, 0.2f, 0.2f, 0.2f, 0.0f};
  write_png(dir + "/a.png", image);
  const Image back = read_image(dir + "/a.png", ImageDecode::srgb_to_linear);
  EXPECT_NEAR(back.at(0, 0, 3), 0.5f, 1.0f / 255.0f);
  // Colour is not premultiplied by alpha, even where alpha is 0.
  EXPECT_NEAR(back.at(0, 0, 1), 0.5f, 0.005f);
  EXPECT_NEAR(back.at(1, 0, 0), 0.2f, 0.005f);
}

TEST(ImageIo, TonemappedPngHoldsTheFormula) {
  const std::string dir = fresh_dir("png_tonemapped");
  Image radiance(3, 1, 3);
  radiance.pixels = {0.0f, 0.0f, 0.0f, 1.0f, 1.0f, 1.0f, 0.25f, 0.25f, 0.25f};
  const ToneMap tone{1.0f, ToneCurve::reinhard};  // 0.25 * 2 = 0.5 -> 1/3; 1 * 2 -> 2/3
  write_png_tonemapped(dir + "/a.png", radiance, tone);
  const Image back = read_image(dir + "/a.png");
  EXPECT_FLOAT_EQ(back.at(0, 0, 0), 0.0f);
  EXPECT_NEAR(back.at(1, 0, 0), srgb_oetf(2.0f / 3.0f), 0.5f / 255.0f + 1e-6f);
  EXPECT_NEAR(back.at(2, 0, 1), srgb_oetf(1.0f / 3.0f), 0.5f / 255.0f + 1e-6f);
}

TEST(ImageIo, ReadErrorsNameTheFile) {
  const std::string dir = fresh_dir("read_errors");
  try {
    read_image(dir + "/missing.png");
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(dir + "/missing.png:"), std::string::npos) << e.what();
  }
  write_text_atomic(dir + "/garbage.png", "this is not a png");
  try {
    read_image(dir + "/garbage.png");
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind(dir + "/garbage.png:", 0), 0u) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

// ---- Metrics ----------------------------------------------------------------------------------

TEST(ImageCompare, MetricsOnConstructedImages) {
  Image reference(4, 2, 1, 1.0f);
  Image image = reference;
  EXPECT_EQ(compare_images(image, reference).rmse, 0.0);
  EXPECT_EQ(compare_images(image, reference).fraction_over, 0.0);

  // One pixel off by 0.4, another by -0.2, six exact.
  image.at(1, 0) = 1.4f;
  image.at(3, 1) = 0.8f;
  const ImageDifference d = compare_images(image, reference, 0.3f, 0.0f);
  EXPECT_EQ(d.pixels, 8u);
  EXPECT_NEAR(d.mean_abs, 0.6 / 8.0, 1e-6);
  EXPECT_NEAR(d.rmse, std::sqrt((0.16 + 0.04) / 8.0), 1e-6);
  EXPECT_NEAR(d.mean_relative, 0.6 / 8.0, 1e-6);  // the reference is 1 everywhere
  EXPECT_NEAR(d.max_abs, 0.4, 1e-6);
  EXPECT_EQ(d.max_x, 1);
  EXPECT_EQ(d.max_y, 0);
  EXPECT_DOUBLE_EQ(d.fraction_over, 1.0 / 8.0);  // only the 0.4 one exceeds 0.3
  EXPECT_DOUBLE_EQ(compare_images(image, reference, 0.1f).fraction_over, 2.0 / 8.0);

  // Relative error divides by the reference.
  Image small_ref(1, 1, 3, 0.5f), small(1, 1, 3, 0.75f);
  EXPECT_NEAR(compare_images(small, small_ref, 0.01f, 0.0f).mean_relative, 0.5, 1e-6);

  // NaN is never "close".
  image.at(0, 0) = NAN;
  EXPECT_TRUE(std::isinf(compare_images(image, reference).max_abs));
  EXPECT_THROW(compare_images(Image(2, 2, 3), Image(2, 2, 1)), std::invalid_argument);
}

TEST(ImageCompare, WriteComparisonLeavesEvidence) {
  const std::string dir = fresh_dir("comparison");
  Image reference(8, 8, 3, 0.5f), image(8, 8, 3, 0.5f);
  image.at(2, 3, 1) = 0.9f;
  const std::string prefix = write_comparison(dir + "/sub", "case", image, reference);
  EXPECT_EQ(prefix, dir + "/sub/case");
  EXPECT_EQ(entries(dir + "/sub"),
            (std::vector<std::string>{"case.exr", "case.png", "case_diff.exr", "case_diff.png",
                                      "case_ref.exr", "case_ref.png"}));
  const Image diff = read_image(prefix + "_diff.exr");
  EXPECT_NEAR(diff.at(2, 3, 1), 0.4f, 1e-6f);
  EXPECT_EQ(diff.at(2, 3, 0), 0.0f);
  EXPECT_EQ(read_image(prefix + "_diff.png").at(2, 3, 1), 1.0f);  // scaled to white
}

// ---- Atomic writes ----------------------------------------------------------------------------

TEST(AtomicFile, WritesAndReplacesWithoutLeftovers) {
  const std::string dir = fresh_dir("atomic");
  write_text_atomic(dir + "/a.json", "{\"x\": 1}");
  EXPECT_EQ(read_text(dir + "/a.json"), "{\"x\": 1}");
  write_text_atomic(dir + "/a.json", "{}", {.sync = true});
  EXPECT_EQ(read_text(dir + "/a.json"), "{}");
  const std::vector<std::byte> bytes{std::byte{0}, std::byte{255}, std::byte{10}};
  write_file_atomic(dir + "/b.bin", bytes);
  EXPECT_EQ(read_text(dir + "/b.bin"), std::string("\0\xff\n", 3));
  EXPECT_EQ(entries(dir), (std::vector<std::string>{"a.json", "b.bin"}));
}

TEST(AtomicFile, MissingDirectoryFailsAndCreatesNothing) {
  const std::string dir = fresh_dir("atomic_missing");
  const std::string path = dir + "/no/such/dir/a.json";
  try {
    write_text_atomic(path, "x");
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()).rfind(path + ":", 0), 0u) << e.what();
  }
  EXPECT_THROW(write_exr(dir + "/missing/a.exr", Image(1, 1, 1)), std::runtime_error);
  EXPECT_THROW(AtomicDirectory(dir + "/missing/bake"), std::runtime_error);
  EXPECT_TRUE(entries(dir).empty());
}

TEST(AtomicFile, FailingWriterLeavesOldFileAndNoTemporary) {
  const std::string dir = fresh_dir("atomic_failing");
  write_text_atomic(dir + "/a.txt", "old");
  EXPECT_THROW(write_via_temp_file(dir + "/a.txt",
                                   [](const std::string& temp) {
                                     std::ofstream(temp) << "half of the new";
                                     throw std::runtime_error("disk full");
                                   }),
               std::runtime_error);
  EXPECT_EQ(read_text(dir + "/a.txt"), "old");
  EXPECT_EQ(entries(dir), std::vector<std::string>{"a.txt"});

  // An image that cannot be written (bad shape) leaves nothing either.
  Image bad(2, 2, 3);
  bad.pixels.resize(5);
  EXPECT_THROW(write_exr(dir + "/bad.exr", bad), std::runtime_error);
  EXPECT_THROW(write_image(dir + "/bad.tga", Image(1, 1, 3)), std::runtime_error);
  EXPECT_EQ(entries(dir), std::vector<std::string>{"a.txt"});
}

// Issue 42: an image and its report appear together or not at all. The second is made from
// the first's temporary (a report records the image's hash); when the second cannot be put in
// place (its name is a folder) or not made, no new first stays, nor any temporary.
TEST(AtomicFile, APairAppearsWholeOrNotAtAll) {
  const std::string dir = fresh_dir("atomic_pair");
  const auto first = [](const std::string& temp) { std::ofstream(temp) << "image"; };
  const auto second = [](const std::string& first_temp) {
    return "report of " + read_text(first_temp);
  };
  write_pair_atomic(dir + "/a.png", first, dir + "/a.json", second);
  EXPECT_EQ(read_text(dir + "/a.png"), "image");
  EXPECT_EQ(read_text(dir + "/a.json"), "report of image");
  EXPECT_EQ(entries(dir), (std::vector<std::string>{"a.json", "a.png"}));

  fs::create_directory(dir + "/b.json");
  try {
    write_pair_atomic(dir + "/b.png", first, dir + "/b.json", second);
    FAIL() << "a report path that is a folder must fail";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()).rfind(dir + "/b.json: ", 0), 0u) << e.what();
  }
  EXPECT_THROW(write_pair_atomic(dir + "/c.png", first, dir + "/c.json",
                                 [](const std::string&) -> std::string {
                                   throw std::runtime_error("disk full");
                                 }),
               std::runtime_error);
  EXPECT_THROW(write_pair_atomic(dir + "/d.png", first, dir + "/missing/d.json", second),
               std::runtime_error);
  EXPECT_EQ(entries(dir), (std::vector<std::string>{"a.json", "a.png", "b.json"}));
  EXPECT_TRUE(fs::is_empty(dir + "/b.json"));
}

TEST(AtomicDirectory, CommitsOrCleansUp) {
  const std::string dir = fresh_dir("atomic_dir");
  {
    AtomicDirectory out(dir + "/bake/");
    EXPECT_EQ(out.final_path(), dir + "/bake");
    write_text_atomic(out.file("manifest.json"), "{\"v\": 1}");
    write_exr(out.file("map.exr"), Image(2, 2, 3, 1.0f));
    EXPECT_FALSE(fs::exists(dir + "/bake"));  // nothing visible before commit
    out.commit();
  }
  EXPECT_EQ(entries(dir), std::vector<std::string>{"bake"});
  EXPECT_EQ(entries(dir + "/bake"), (std::vector<std::string>{"manifest.json", "map.exr"}));

  // Replacing an existing directory: new files win, superseded ones go, any other old entry
  // (a file, a folder) is carried over, hard-linked rather than copied.
  write_text_atomic(dir + "/bake/notes.txt", "mine");
  const auto links_before = fs::hard_link_count(dir + "/bake/notes.txt");
  {
    AtomicDirectory out(dir + "/bake", {"map.exr"});
    write_text_atomic(out.file("manifest.json"), "{\"v\": 2}");
    out.commit();
  }
  EXPECT_EQ(entries(dir + "/bake"), (std::vector<std::string>{"manifest.json", "notes.txt"}));
  EXPECT_EQ(read_text(dir + "/bake/notes.txt"), "mine");
  EXPECT_EQ(fs::hard_link_count(dir + "/bake/notes.txt"), links_before);
  EXPECT_EQ(read_text(dir + "/bake/manifest.json"), "{\"v\": 2}");
  EXPECT_EQ(entries(dir), std::vector<std::string>{"bake"});

  // Abandoned (an exception mid-bake): the old directory stays, the temporary goes.
  try {
    AtomicDirectory out(dir + "/bake");
    write_text_atomic(out.file("manifest.json"), "{\"v\": 3}");
    throw std::runtime_error("cancelled");
  } catch (const std::runtime_error&) {
  }
  EXPECT_EQ(entries(dir), std::vector<std::string>{"bake"});
  EXPECT_EQ(read_text(dir + "/bake/manifest.json"), "{\"v\": 2}");
}

}  // namespace
}  // namespace lb
