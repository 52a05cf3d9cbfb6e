// sample_texture: bilinear between texel centres, repeat wrap in both axes (negative and far
// coordinates included), one channel broadcast to grey with alpha 1; glTF's other samplers:
// nearest texel, clamp to edge, mirrored repeat (OpenGL's rules).

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

// NEAREST (Blender's Closest): the texel the point lies in, whole, anywhere inside it.
TEST(TextureSampling, NearestGivesTheTexelItLiesIn) {
  Texture texture = ramp();
  texture.filter = TextureFilter::nearest;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 3; ++i)
      for (const vec2 inside : {vec2(0.01f, 0.01f), vec2(0.99f, 0.5f), vec2(0.5f, 0.99f)}) {
        const vec2 uv((float(i) + inside.x) / 3.0f, (float(j) + inside.y) / 2.0f);
        EXPECT_EQ(sample_texture(texture, uv).x, float(10 * j + i)) << i << " " << j;
        EXPECT_EQ(sample_texture(texture, uv + vec2(-2, 3)).x, float(10 * j + i));  // repeated
      }
}

// CLAMP_TO_EDGE: beyond the edge texels' centres the edge's value, no blend across the edge.
TEST(TextureSampling, ClampHoldsTheEdge) {
  Texture texture = ramp();
  texture.wrap_u = texture.wrap_v = TextureWrap::clamp;
  EXPECT_NEAR(sample_texture(texture, {0.0f, 0.25f}).x, 0.0f, 1e-6f);  // repeat: 1
  EXPECT_NEAR(sample_texture(texture, {-5.0f, -5.0f}).x, 0.0f, 1e-6f);
  EXPECT_NEAR(sample_texture(texture, {7.0f, 9.0f}).x, 12.0f, 1e-6f);
  EXPECT_NEAR(sample_texture(texture, {0.5f, 0.0f}).x, 1.0f, 1e-5f);  // repeat: 6
  texture.filter = TextureFilter::nearest;
  EXPECT_EQ(sample_texture(texture, {1.7f, -0.2f}).x, 2.0f);
}

// MIRRORED_REPEAT: the image, then its mirror image, and so on; so across u = 0 the first
// column meets itself (a blend of equal texels) and u in (1, 2) reads the columns backwards.
TEST(TextureSampling, MirrorReflectsAtEveryEdge) {
  Texture texture = ramp();
  texture.wrap_u = texture.wrap_v = TextureWrap::mirror;
  EXPECT_NEAR(sample_texture(texture, {0.0f, 0.25f}).x, 0.0f, 1e-6f);
  EXPECT_NEAR(sample_texture(texture, {1.0f, 0.25f}).x, 2.0f, 1e-5f);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(sample_texture(texture, vec2(-centre(i, 0).x, 0.25f)).x, float(i),
                1e-5f);  // -u: the mirror
    EXPECT_NEAR(sample_texture(texture, vec2(2.0f - centre(i, 0).x, 0.25f)).x, float(i), 1e-5f);
    EXPECT_NEAR(sample_texture(texture, vec2(2.0f + centre(i, 0).x, 0.25f)).x, float(i), 1e-5f);
  }
  EXPECT_NEAR(sample_texture(texture, {1.0f / 6.0f, -0.25f}).x, 0.0f, 1e-5f);  // row 0 again
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
