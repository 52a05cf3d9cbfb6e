// sample_texture: bilinear between texel centres, repeat wrap in both axes (negative and far
// coordinates included), one channel broadcast to grey with alpha 1.

#include <gtest/gtest.h>

#include "bake/surface.h"

namespace lb {
namespace {

// 3 x 2 texels, two channels: texel (i, j) = (10 j + i, -(10 j + i)).
Texture ramp() {
  Texture texture;
  texture.width = 3;
  texture.height = 2;
  texture.channels = 2;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 3; ++i) {
      texture.texels.push_back(float(10 * j + i));
      texture.texels.push_back(-float(10 * j + i));
    }
  return texture;
}

vec2 centre(int i, int j) {
  return {(float(i) + 0.5f) / 3.0f, (float(j) + 0.5f) / 2.0f};
}

TEST(TextureSampling, TexelCentresGiveTheirTexels) {
  const Texture texture = ramp();
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 3; ++i) {
      const vec4 v = sample_texture(texture, centre(i, j));
      EXPECT_NEAR(v.x, float(10 * j + i), 1e-5f) << i << " " << j;
      EXPECT_NEAR(v.y, -float(10 * j + i), 1e-5f);
      EXPECT_EQ(v.z, 1.0f);  // channels the texture lacks
      EXPECT_EQ(v.w, 1.0f);
    }
}

TEST(TextureSampling, RepeatWrapsBothWaysAndBlendsAcrossTheEdge) {
  const Texture texture = ramp();
  for (const vec2 shift : {vec2(1, 0), vec2(-1, 0), vec2(-3, 2), vec2(5, -7), vec2(-1000, 1000)})
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 3; ++i)
        EXPECT_NEAR(sample_texture(texture, centre(i, j) + shift).x, float(10 * j + i), 1e-3f)
            << shift.x << " " << shift.y;
  // u = 0 lies halfway between the last column's centre and the first's: (2 + 0) / 2 on row 0.
  EXPECT_NEAR(sample_texture(texture, {0.0f, 0.25f}).x, 1.0f, 1e-5f);
  // v = 0 halfway between the rows (wrapped): (0 + 10) / 2 in column 0.
  EXPECT_NEAR(sample_texture(texture, {1.0f / 6.0f, 0.0f}).x, 5.0f, 1e-5f);
  // The corner blends all four corner texels: (0 + 2 + 10 + 12) / 4.
  EXPECT_NEAR(sample_texture(texture, {0.0f, 0.0f}).x, 6.0f, 1e-5f);
}

TEST(TextureSampling, OneChannelIsGrey) {
  Texture texture;
  texture.width = texture.height = 1;
  texture.channels = 1;
  texture.texels = {0.25f};
  EXPECT_EQ(sample_texture(texture, {-0.3f, 7.9f}), vec4(0.25f, 0.25f, 0.25f, 1.0f));
}

}  // namespace
}  // namespace lb
