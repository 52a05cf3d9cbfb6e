// The split of a lightmap's node rows into shards (`lightbake export --shard i/n`,
// texel_footprint.h): contiguous ranges of about 1/n of the rows' work each.

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>

#include "bake/lightmap/texel_footprint.h"
#include "half_atlas_triangle.h"

namespace lb {
namespace {

// half_atlas_triangle.h: bands of 32 rows hold very unequal work.
using half_atlas::kHeight;
using half_atlas::kWidth;
Mesh half_atlas_triangle() { return half_atlas::triangle(); }

double work_of(const std::vector<double>& work, TexelRows rows) {
  return std::accumulate(work.begin() + rows.begin, work.begin() + rows.end, 0.0);
}

// The ranges follow each other from row 0 to the last and hold each within the largest row's
// work of 1/n of the total (partition_texel_rows's promise).
void expect_balanced_cover(const std::vector<double>& work, const std::vector<TexelRows>& ranges,
                           int count) {
  ASSERT_EQ(ranges.size(), size_t(count));
  const double total = std::accumulate(work.begin(), work.end(), 0.0);
  const double largest_row = *std::max_element(work.begin(), work.end());
  int next_row = 0;
  for (size_t k = 0; k < ranges.size(); ++k) {
    EXPECT_EQ(ranges[k].begin, next_row) << "shard " << k;
    EXPECT_GE(ranges[k].count(), 0) << "shard " << k;
    next_row = ranges[k].end;
    EXPECT_NEAR(work_of(work, ranges[k]), total / count, largest_row) << "shard " << k;
  }
  EXPECT_EQ(next_row, int(work.size()));
}

TEST(TexelPartition, RowWorkIsTheSurfaceInEachCellRow) {
  const Mesh mesh = half_atlas_triangle();
  const TexelFootprints footprints({&mesh}, kWidth, kHeight);
  const std::vector<double> work = texel_row_work(footprints);
  ASSERT_EQ(work.size(), size_t(kHeight));
  // In node space (uv x size - 0.5) the triangle's legs run from -0.5; the cells cover x, y >= 0,
  // where its hypotenuse meets the axes at x = 63.18 and y = 98.71875.
  EXPECT_NEAR(std::accumulate(work.begin(), work.end(), 0.0), 0.5 * 63.18 * 98.71875, 0.01);
  // Cell row 0 spans y 0..1: full cells up to x = 62.54, then the hypotenuse's slope.
  EXPECT_NEAR(work[0], 0.5 * (63.18 + 62.54), 1e-3);
  EXPECT_EQ(work[kHeight - 1], 0.0);  // above y = 98.72
  EXPECT_TRUE(std::is_sorted(work.rbegin(), work.rend()));
}

TEST(TexelPartition, ShardsHoldAboutAnEqualShareOfWorkWhereBandsDoNot) {
  const Mesh mesh = half_atlas_triangle();
  const TexelFootprints footprints({&mesh}, kWidth, kHeight);
  const std::vector<double> work = texel_row_work(footprints);
  const double total = std::accumulate(work.begin(), work.end(), 0.0);
  const double largest_row = *std::max_element(work.begin(), work.end());
  ASSERT_LT(largest_row, 0.1 * total / 4);  // so the tolerance below is under 10% of a quarter
  for (int count : {2, 3, 4, 7}) {
    SCOPED_TRACE(count);
    expect_balanced_cover(work, partition_texel_rows(work, count), count);
  }
  // The old split (bands of kTexelBandRows, band b to shard b mod 4) gave shard 0 over twice
  // its share here: bands 0..3 hold 54%, 33%, 13% and 0.1% of the work.
  double band_shard0 = 0.0;
  for (int j = 0; j < kHeight; ++j)
    if ((j / kTexelBandRows) % 4 == 0) band_shard0 += work[size_t(j)];
  EXPECT_GT(band_shard0, 2.0 * total / 4);
  // Bottom rows weigh more: the first quarter of the work is in fewer rows than the last.
  const std::vector<TexelRows> four = partition_texel_rows(work, 4);
  EXPECT_LT(four[0].count(), four[3].count());
}

TEST(TexelPartition, OneShardIsTheWholeAndMoreShardsThanRowsLeaveSomeEmpty) {
  const Mesh mesh = half_atlas_triangle();
  const TexelFootprints footprints({&mesh}, kWidth, kHeight);
  const std::vector<double> work = texel_row_work(footprints);
  EXPECT_EQ(partition_texel_rows(work, 1), (std::vector<TexelRows>{{0, kHeight}}));
  const int many = 3 * kHeight;
  const std::vector<TexelRows> ranges = partition_texel_rows(work, many);
  expect_balanced_cover(work, ranges, many);
  const auto filled =
      std::count_if(ranges.begin(), ranges.end(), [](TexelRows r) { return r.count() > 0; });
  EXPECT_LE(filled, kHeight);
  EXPECT_GT(filled, kHeight / 2);  // most rows are a shard's alone
  // Two rows, five shards: each row to the shard whose share it is nearest.
  EXPECT_EQ(partition_texel_rows(std::vector<double>{1.0, 1.0}, 5),
            (std::vector<TexelRows>{{0, 0}, {0, 1}, {1, 1}, {1, 2}, {2, 2}}));
}

TEST(TexelPartition, WithoutSurfaceRowsSplitByCount) {
  const TexelFootprints empty({}, kWidth, 10);
  const std::vector<double> work = texel_row_work(empty);
  EXPECT_EQ(work, std::vector<double>(10, 0.0));
  EXPECT_EQ(partition_texel_rows(work, 3), (std::vector<TexelRows>{{0, 3}, {3, 6}, {6, 10}}));
  EXPECT_EQ(partition_texel_rows(std::vector<double>{}, 2),
            (std::vector<TexelRows>{{0, 0}, {0, 0}}));
}

}  // namespace
}  // namespace lb
