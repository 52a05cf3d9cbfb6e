// The soft map's interleaved strata (bake/lightmap/interleaved_strata.h): which sub-squares of
// the direction square neighbouring cells take.
#include <gtest/gtest.h>

#include <set>
#include <utility>

#include "bake/lightmap/interleaved_strata.h"

namespace lb {
namespace {

// Sub-square index (column, row) of a cell at `levels`.
std::pair<int, int> index_of(const SampleCell& s) {
  return {int(s.origin.x / s.size.x + 0.5f), int(s.origin.y / s.size.y + 0.5f)};
}

TEST(InterleavedStrata, ZeroLevelsIsTheWholeSquare) {
  const SampleCell s = interleaved_stratum(5, 9, 0, 1234);
  EXPECT_EQ(s.origin, vec2(0.0f));
  EXPECT_EQ(s.size, vec2(1.0f));
}

// Every 2 x 2 window of cells, aligned or not, takes one sub-square in each quadrant (a node's
// four cells), and every aligned 2^k x 2^k window one in each block of side 2^-k, for every
// level count and several scrambles.
TEST(InterleavedStrata, WindowsCoverEveryBlock) {
  for (int levels = 1; levels <= kMaxStrataLevels; ++levels) {
    const int side = 1 << levels;
    for (uint64_t scramble : {uint64_t(0), uint64_t(0x9e3779b97f4a7c15ull), ~uint64_t(0)}) {
      for (int y0 = 0; y0 < 2 * side; ++y0)
        for (int x0 = 0; x0 < 2 * side; ++x0) {
          std::set<std::pair<int, int>> quadrants;
          for (int dy = 0; dy < 2; ++dy)
            for (int dx = 0; dx < 2; ++dx) {
              const SampleCell s = interleaved_stratum(x0 + dx, y0 + dy, levels, scramble);
              EXPECT_FLOAT_EQ(s.size.x, 1.0f / float(side));
              quadrants.insert({int(s.origin.x * 2.0f), int(s.origin.y * 2.0f)});
            }
          EXPECT_EQ(quadrants.size(), 4u) << "levels " << levels << " at " << x0 << "," << y0;
        }
      for (int k = 1; k <= levels; ++k) {
        const int window = 1 << k;
        for (int y0 = 0; y0 < 2 * side; y0 += window)
          for (int x0 = 0; x0 < 2 * side; x0 += window) {
            std::set<std::pair<int, int>> blocks;
            for (int dy = 0; dy < window; ++dy)
              for (int dx = 0; dx < window; ++dx) {
                const auto [i, j] = index_of(interleaved_stratum(x0 + dx, y0 + dy, levels, scramble));
                blocks.insert({i >> (levels - k), j >> (levels - k)});
              }
            EXPECT_EQ(blocks.size(), size_t(window * window)) << "levels " << levels << " k " << k;
          }
      }
    }
  }
}

// Over the scramble, a cell's sub-square is uniform: each of the 4^L sub-squares is taken by
// one scramble value of the 4^L that differ in their low L bits per axis.
TEST(InterleavedStrata, ScrambleVisitsEverySubSquare) {
  const int levels = 2, side = 4;
  std::set<std::pair<int, int>> seen;
  for (uint64_t sy = 0; sy < uint64_t(side); ++sy)
    for (uint64_t sx = 0; sx < uint64_t(side); ++sx)
      seen.insert(index_of(interleaved_stratum(3, 6, levels, sx | (sy << 32))));
  EXPECT_EQ(seen.size(), size_t(side * side));
}

}  // namespace
}  // namespace lb
