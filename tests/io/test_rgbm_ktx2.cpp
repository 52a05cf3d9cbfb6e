// RGBM for block compression (bake/export/rgbm_blocks.h) and the KTX2 level joiner
// (bake/io/ktx2_encode.h): closed forms, no encoder needed. The three.js check (ctest
// export_threejs) reads the encoded file.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iterator>
#include <random>

#include "bake/export/rgbm_blocks.h"
#include "bake/io/ktx2_encode.h"

namespace lb {
namespace {

// A map over six decades of brightness with a bright spot: what per-texel RGBM is for.
std::vector<vec3> test_map(int width, int height) {
  std::mt19937 random(7);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<vec3> map(size_t(width) * size_t(height));
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const float decade = std::pow(10.0f, -6.0f * float(x + y) / float(width + height));
      map[size_t(y) * size_t(width) + size_t(x)] =
          decade * vec3(unit(random), unit(random), unit(random)) * 20.0f;
    }
  map[3] = vec3(40.0f, 10.0f, 1.0f);
  return map;
}

vec3 decode(const uint8_t* texel, float scale) {
  return vec3(texel[0], texel[1], texel[2]) / 255.0f * (float(texel[3]) / 255.0f) * scale;
}

// Alpha constant over each 4x4 block, the smallest listed multiplier at or above the block's
// largest value (so no colour byte clips), and every texel within half a colour step of its
// block's multiplier: 0.5/255 of m.
TEST(RgbmBlocks, OneMultiplierPerBlockAndHalfAStepOfIt) {
  const int width = 13, height = 10;  // partial blocks at both far edges
  const std::vector<vec3> map = test_map(width, height);
  const float scale = 40.0f;
  const std::vector<uint8_t> rgba = encode_rgbm_blocks(width, height, map, scale);
  ASSERT_EQ(rgba.size(), map.size() * 4);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const size_t i = size_t(y) * size_t(width) + size_t(x);
      float block_top = 0.0f;
      for (int by = y / 4 * 4; by < std::min(y / 4 * 4 + 4, height); ++by)
        for (int bx = x / 4 * 4; bx < std::min(x / 4 * 4 + 4, width); ++bx) {
          const vec3& r = map[size_t(by) * size_t(width) + size_t(bx)];
          block_top = std::max({block_top, r.x, r.y, r.z});
        }
      const int m = rgba[i * 4 + 3];
      const int need = int(std::ceil(block_top / scale * 255.0f));
      const uint8_t* fits = std::lower_bound(std::begin(kBlockMultipliers),
                                             std::end(kBlockMultipliers), need);
      ASSERT_NE(fits, std::end(kBlockMultipliers));
      EXPECT_EQ(m, *fits) << x << "," << y;  // the smallest that fits
      const vec3 decoded = decode(&rgba[i * 4], scale);
      for (int c = 0; c < 3; ++c)
        EXPECT_LE(std::abs(decoded[c] - map[i][c]), 0.5f / 255.0f * float(m) / 255.0f * scale *
                                                        1.0001f)
            << x << "," << y << " channel " << c;
    }
  // The brightest texel keeps 8 bits of itself: within 1/255 relative.
  const vec3 top = decode(&rgba[3 * 4], scale);
  EXPECT_NEAR(top.x, 40.0f, 40.0f / 255.0f);
}

// The multipliers: ascending, neighbours at most 2x apart, up to 255 (m = 1, the scale).
TEST(RgbmBlocks, MultipliersAscendAtMostTwiceApart) {
  const auto& m = kBlockMultipliers;
  EXPECT_EQ(m[std::size(m) - 1], 255);
  for (size_t k = 1; k < std::size(m); ++k) {
    EXPECT_GT(m[k], m[k - 1]);
    EXPECT_LE(m[k], 2 * m[k - 1]);
  }
}

// The box mean of a level keeps the mean (energy) exactly, halves odd sides down as KTX2 does,
// and of a 2 x 2 checker leaves the checker's mean everywhere.
TEST(RgbmBlocks, BoxDownsampleKeepsTheMeanAtEverySize) {
  for (const auto& [width, height] : {std::pair{8, 6}, std::pair{13, 10}, std::pair{5, 1}}) {
    const std::vector<vec3> map = test_map(width, height);
    const std::vector<vec3> half = box_downsample(width, height, map);
    const int to_width = std::max(1, width / 2), to_height = std::max(1, height / 2);
    ASSERT_EQ(half.size(), size_t(to_width) * size_t(to_height));
    double sum = 0.0, half_sum = 0.0;
    for (const vec3& r : map) sum += double(r.x + r.y + r.z);
    for (const vec3& r : half) half_sum += double(r.x + r.y + r.z);
    EXPECT_NEAR(half_sum / double(half.size()), sum / double(map.size()),
                1e-5 * sum / double(map.size()))
        << width << "x" << height;
  }
  std::vector<vec3> checker(16);
  for (int i = 0; i < 16; ++i) checker[size_t(i)] = vec3(float((i % 4 + i / 4) % 2) * 2.0f);
  for (const vec3& r : box_downsample(4, 4, checker)) EXPECT_FLOAT_EQ(r.x, 1.0f);
  // 5 texels to 2: each takes 2.5 of them, the middle one shared half and half.
  const std::vector<vec3> row = {vec3(1), vec3(2), vec3(3), vec3(4), vec3(5)};
  const std::vector<vec3> two = box_downsample(5, 1, row);
  ASSERT_EQ(two.size(), 2u);
  EXPECT_FLOAT_EQ(two[0].x, (1.0f + 2.0f + 1.5f) / 2.5f);
  EXPECT_FLOAT_EQ(two[1].x, (1.5f + 4.0f + 5.0f) / 2.5f);
}

// The chain runs to 1 x 1 at KTX2's sizes; the last level decodes to the map's mean within
// half a step of its one multiplier.
TEST(RgbmBlocks, LevelsRunToOneTexelAndKeepTheMean) {
  const int width = 12, height = 8;
  const std::vector<vec3> map = test_map(width, height);
  const float scale = 40.0f;
  const std::vector<RgbmLevel> levels = rgbm_block_levels(width, height, map, scale, true);
  ASSERT_EQ(levels.size(), 4u);  // 12x8, 6x4, 3x2, 1x1
  for (size_t k = 0; k < levels.size(); ++k) {
    EXPECT_EQ(levels[k].width, std::max(1, width >> k));
    EXPECT_EQ(levels[k].height, std::max(1, height >> k));
  }
  vec3 mean(0.0f);
  for (const vec3& r : map) mean += r / float(map.size());
  const RgbmLevel& last = levels.back();
  const vec3 decoded = decode(last.rgba.data(), scale);
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(decoded[c], mean[c], 0.5f / 255.0f * float(last.rgba[3]) / 255.0f * scale);
  EXPECT_EQ(rgbm_block_levels(width, height, map, scale, false).size(), 1u);
}

// ---- KTX2 levels joined ------------------------------------------------------------------

void put(std::vector<unsigned char>& bytes, size_t at, uint64_t value, size_t size) {
  for (size_t i = 0; i < size; ++i) bytes[at + i] = (unsigned char)(value >> (8 * i));
}
uint64_t get(const std::vector<unsigned char>& bytes, size_t at, size_t size) {
  uint64_t value = 0;
  for (size_t i = 0; i < size; ++i) value |= uint64_t(bytes[at + i]) << (8 * i);
  return value;
}

// A single-level KTX2 as basisu writes one (UASTC, Zstandard): a descriptor, key/values and
// `data` as the level.
std::vector<unsigned char> one_level(uint32_t width, uint32_t height,
                                     const std::vector<unsigned char>& data) {
  static constexpr unsigned char kIdentifier[12] = {0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32,
                                                    0x30, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A};
  std::vector<unsigned char> file(104 + 8 + 12, 0);
  std::memcpy(file.data(), kIdentifier, 12);
  put(file, 16, 1, 4);  // typeSize
  put(file, 20, width, 4);
  put(file, 24, height, 4);
  put(file, 32, 0, 4);
  put(file, 36, 1, 4);  // faces
  put(file, 40, 1, 4);  // levels
  put(file, 44, 2, 4);  // Zstandard
  put(file, 48, 104, 4);
  put(file, 52, 8, 4);  // the descriptor: 8 bytes 'D'
  put(file, 56, 112, 4);
  put(file, 60, 12, 4);  // key/values: 12 bytes 'K'
  std::fill(file.begin() + 104, file.begin() + 112, 'D');
  std::fill(file.begin() + 112, file.begin() + 124, 'K');
  put(file, 80, file.size(), 8);
  put(file, 88, data.size(), 8);
  put(file, 96, data.size() * 3, 8);  // uncompressed
  file.insert(file.end(), data.begin(), data.end());
  return file;
}

TEST(Ktx2Join, LevelsInOrderSmallestDataFirst) {
  const std::vector<std::vector<unsigned char>> data = {
      std::vector<unsigned char>(50, 'a'), std::vector<unsigned char>(20, 'b'),
      std::vector<unsigned char>(7, 'c')};
  const std::vector<unsigned char> joined = join_ktx2_levels(
      {one_level(12, 8, data[0]), one_level(6, 4, data[1]), one_level(3, 2, data[2])});
  ASSERT_TRUE(is_ktx2_data(joined.data(), joined.size()));
  EXPECT_EQ(get(joined, 20, 4), 12u);
  EXPECT_EQ(get(joined, 24, 4), 8u);
  EXPECT_EQ(get(joined, 40, 4), 3u);
  const size_t dfd = get(joined, 48, 4), kvd = get(joined, 56, 4);
  EXPECT_EQ(dfd, 80u + 3u * 24u);  // right after the level index
  EXPECT_EQ(get(joined, 52, 4), 8u);
  EXPECT_EQ(kvd, dfd + 8u);
  EXPECT_EQ(joined[dfd], 'D');
  EXPECT_EQ(joined[kvd + 11], 'K');
  size_t previous_at = joined.size();
  for (size_t k = 0; k < 3; ++k) {
    const size_t at = get(joined, 80 + 24 * k, 8), size = get(joined, 88 + 24 * k, 8);
    EXPECT_EQ(size, data[k].size());
    EXPECT_EQ(get(joined, 96 + 24 * k, 8), data[k].size() * 3);
    ASSERT_LE(at + size, joined.size());
    EXPECT_TRUE(std::equal(data[k].begin(), data[k].end(), joined.begin() + long(at)));
    EXPECT_LT(at, previous_at);  // level 0's data last
    previous_at = at;
  }
  EXPECT_EQ(get(joined, 80 + 24 * 2, 8), kvd + 12u);  // the smallest level first
  EXPECT_EQ(get(joined, 80, 8) + data[0].size(), joined.size());
}

TEST(Ktx2Join, RefusesLevelsThatDoNotFit) {
  const std::vector<unsigned char> level(16, 'x');
  EXPECT_THROW(join_ktx2_levels({one_level(12, 8, level), one_level(5, 4, level)}),
               std::runtime_error);
  std::vector<unsigned char> other_format = one_level(6, 4, level);
  put(other_format, 44, 0, 4);
  EXPECT_THROW(join_ktx2_levels({one_level(12, 8, level), other_format}), std::runtime_error);
  std::vector<unsigned char> cut = one_level(6, 4, level);
  cut.resize(cut.size() - 1);
  EXPECT_THROW(join_ktx2_levels({one_level(12, 8, level), cut}), std::runtime_error);
  EXPECT_THROW(join_ktx2_levels({}), std::runtime_error);
}

}  // namespace
}  // namespace lb
