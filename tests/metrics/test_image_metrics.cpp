// Error metrics against hand-made images whose values are known in closed form
// (definitions in bake/metrics/image_metrics.h).

#include <gtest/gtest.h>

#include <cmath>

#include <stdexcept>

#include "bake/metrics/error_image.h"
#include "bake/metrics/image_metrics.h"

namespace lb {
namespace {

// Sums of at most 64 x 48 doubles: far below 1e-12 relative rounding.
constexpr double kTight = 1e-12;

Image constant(float r, float g, float b, int width = 64, int height = 48) {
  Image image(width, height, 3);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      image.at(x, y, 0) = r;
      image.at(x, y, 1) = g;
      image.at(x, y, 2) = b;
    }
  return image;
}

TEST(ImageMetrics, TenPercentBrighterEverywhere) {
  // A = 1.1 B with B = 1: eps = 0.01 * mean(B) = 0.01, so MRE = 0.1 / 1.01,
  // relMSE = 0.01 / (1 + 1e-4), RMSE = 0.1, every sum ratio 1.1.
  const ImageMetrics m = compare_to_reference(constant(1.1f, 1.1f, 1.1f), constant(1, 1, 1));
  const double a = double(1.1f);  // the float the image holds
  EXPECT_NEAR(m.epsilon, 0.01, kTight);
  EXPECT_NEAR(m.mean_relative_error, (a - 1.0) / 1.01, kTight);
  EXPECT_NEAR(m.relative_mse, (a - 1.0) * (a - 1.0) / (1.0 + 1e-4), kTight);
  EXPECT_NEAR(m.rmse, a - 1.0, kTight);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(m.sum_ratio[size_t(c)], a, kTight);
  EXPECT_NEAR(m.sum_ratio_total, a, kTight);
  EXPECT_EQ(m.pixels, 64u * 48u);
  EXPECT_EQ(m.channels, 3);
  EXPECT_EQ(m.differing_values, 64u * 48u * 3u);
  // Bit for bit: one value off by one ulp is counted.
  Image b = constant(1, 1, 1);
  EXPECT_EQ(compare_to_reference(b, b).differing_values, 0u);
  Image c = b;
  c.at(5, 7, 1) = std::nextafter(1.0f, 2.0f);
  EXPECT_EQ(compare_to_reference(c, b).differing_values, 1u);
}

TEST(ImageMetrics, SumRatioPerChannelAndTotal) {
  // A = (2, 1, 0.5) against B = (1, 1, 1): ratios 2, 1, 0.5; total 3.5 / 3.
  const ImageMetrics m = compare_to_reference(constant(2, 1, 0.5f), constant(1, 1, 1));
  EXPECT_NEAR(m.sum_ratio[0], 2.0, kTight);
  EXPECT_NEAR(m.sum_ratio[1], 1.0, kTight);
  EXPECT_NEAR(m.sum_ratio[2], 0.5, kTight);
  EXPECT_NEAR(m.sum_ratio_total, 3.5 / 3.0, kTight);
  // MRE = (1 + 0 + 0.5) / 3 / 1.01
  EXPECT_NEAR(m.mean_relative_error, 1.5 / 3.0 / 1.01, kTight);
}

TEST(ImageMetrics, EpsilonFollowsTheReferenceScaleOrIsGiven) {
  // The same 10% error on a reference 100 times brighter gives the same MRE ...
  const ImageMetrics bright =
      compare_to_reference(constant(110, 110, 110), constant(100, 100, 100));
  EXPECT_NEAR(bright.epsilon, 1.0, kTight);
  EXPECT_NEAR(bright.mean_relative_error, 10.0 / 101.0, kTight);
  // ... and an absolute eps of 0.1 changes it to 0.1 / 1.1 on B = 1.
  CompareParams params;
  params.epsilon = 0.1;
  const ImageMetrics given = compare_to_reference(constant(1.1f, 1.1f, 1.1f), constant(1, 1, 1),
                                                  params);
  EXPECT_NEAR(given.mean_relative_error, (double(1.1f) - 1.0) / 1.1, kTight);
}

// B = 1 everywhere; A = 1 except a 10 x 8 block at (20, 10) where it is 1.5.
struct BlockPair {
  Image a = constant(1, 1, 1);
  Image b = constant(1, 1, 1);
  BlockPair() {
    for (int y = 10; y < 18; ++y)
      for (int x = 20; x < 30; ++x)
        for (int c = 0; c < 3; ++c) a.at(x, y, c) = 1.5f;
  }
};

TEST(ImageMetrics, RegionSelectsPixels) {
  const BlockPair pair;
  CompareParams params;
  params.region = parse_region("20,10,30,18");  // exactly the block
  const ImageMetrics inside = compare_to_reference(pair.a, pair.b, params);
  EXPECT_EQ(inside.pixels, 80u);
  EXPECT_NEAR(inside.mean_relative_error, 0.5 / 1.01, kTight);
  EXPECT_NEAR(inside.sum_ratio_total, 1.5, kTight);

  params.region = parse_region("0,0,20,48");  // left of the block
  const ImageMetrics outside = compare_to_reference(pair.a, pair.b, params);
  EXPECT_EQ(outside.pixels, 20u * 48u);
  EXPECT_EQ(outside.mean_relative_error, 0.0);
  EXPECT_EQ(outside.sum_ratio_total, 1.0);

  // Whole image: 80 of 3072 pixels are 50% off.
  const ImageMetrics whole = compare_to_reference(pair.a, pair.b);
  EXPECT_NEAR(whole.sum_ratio_total, (3072.0 + 0.5 * 80.0) / 3072.0, kTight);
  EXPECT_NEAR(whole.mean_relative_error, 80.0 / 3072.0 * 0.5 / 1.01, kTight);
}

TEST(ImageMetrics, MaskSelectsPixelsAndCombinesWithTheRegion) {
  const BlockPair pair;
  Image mask(64, 48, 1, 0.0f);
  for (int y = 10; y < 14; ++y)  // the top half of the block, and 5 columns right of it
    for (int x = 20; x < 35; ++x) mask.at(x, y) = 1.0f;
  CompareParams params;
  params.mask = &mask;
  const ImageMetrics masked = compare_to_reference(pair.a, pair.b, params);
  EXPECT_EQ(masked.pixels, 60u);
  EXPECT_NEAR(masked.sum_ratio_total, (60.0 + 0.5 * 40.0) / 60.0, kTight);

  params.region = parse_region("25,0,64,48");  // mask and region: x in [25, 35), y in [10, 14)
  const ImageMetrics both = compare_to_reference(pair.a, pair.b, params);
  EXPECT_EQ(both.pixels, 40u);
  EXPECT_NEAR(both.sum_ratio_total, (40.0 + 0.5 * 20.0) / 40.0, kTight);

  const Image error = relative_error_image(pair.a, pair.b, params, 0.01);
  EXPECT_EQ(error.at(0, 0), -1.0f) << "not compared";
  EXPECT_EQ(error.at(30, 12), 0.0f);
  EXPECT_NEAR(error.at(25, 12), 0.5 / 1.01, 1e-6);
}

TEST(ImageMetrics, SubtractGivesTheReferenceMinusATerm) {
  // Reference 1.0, the "direct" term 0.6: A = 0.44 against B - C = 0.4 is 10% bright.
  const Image rest = subtract_images(constant(1, 1, 1), constant(0.6f, 0.6f, 0.6f));
  const ImageMetrics m = compare_to_reference(constant(0.44f, 0.44f, 0.44f), rest);
  EXPECT_NEAR(m.sum_ratio_total, 1.1, 1e-6);  // float images: 1e-7 relative per value
}

TEST(ImageMetrics, RejectsMismatchedSizesRegionsAndMasks) {
  const Image a = constant(1, 1, 1, 64, 48);
  try {
    compare_to_reference(a, constant(1, 1, 1, 64, 47));
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "B: size 64x47 differs from A's 64x48");
  }
  CompareParams params;
  params.region = parse_region("0,0,65,48");
  EXPECT_THROW(compare_to_reference(a, a, params), std::invalid_argument);
  const Image small_mask(32, 48, 1, 1.0f);
  CompareParams masked;
  masked.mask = &small_mask;
  EXPECT_THROW(compare_to_reference(a, a, masked), std::invalid_argument);
  const Image empty_mask(64, 48, 1, 0.0f);
  masked.mask = &empty_mask;
  EXPECT_THROW(compare_to_reference(a, a, masked), std::invalid_argument);
  EXPECT_THROW(parse_region("1,2,3"), std::invalid_argument);
  EXPECT_THROW(parse_region("5,0,4,8"), std::invalid_argument);
  EXPECT_THROW(parse_region("0,0,4,8x"), std::invalid_argument);
}

TEST(ImageMetrics, FalseColourRampIsMonotoneInBrightness) {
  float previous = -1.0f;
  for (int i = 0; i <= 20; ++i) {
    const auto rgb = false_colour(0.05 * i, 1.0);
    const float luminance = 0.2126f * rgb[0] + 0.7152f * rgb[1] + 0.0722f * rgb[2];
    EXPECT_GT(luminance, previous) << "at error " << 0.05 * i;
    previous = luminance;
  }
  EXPECT_EQ(false_colour(0.0, 1.0)[0], 0.0f);
}

}  // namespace
}  // namespace lb
