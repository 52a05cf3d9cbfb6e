#pragma once
// Interleaved strata for the soft-light map's gather (soft_texels.h; interleaved sampling,
// Keller and Heidrich 2001): each texel cell's gather rays cover one sub-square of the
// direction square, and neighbouring cells cover the others, so the rays that one node and
// one correction box average are stratified over the whole hemisphere rather than drawn again
// at every cell.
//
// With L levels the square is cut into 2^L x 2^L sub-squares; cell (x, y) takes sub-square
// (reverse_L(x mod 2^L) ^ sx, reverse_L(y mod 2^L) ^ sy), reverse_L reversing the low L bits
// and (sx, sy) an L-bit scramble from the seed. Reversal puts the lowest bit of the cell's
// coordinate in the highest of the sub-square's, so
//   - any 2 x 2 cells (the four cells of a node) take one sub-square in each quadrant, and
//   - any aligned 2^k x 2^k cells (k <= L) take one in each of the 4^k blocks of side 2^-k,
// whatever the scramble (an XOR permutes each level's halves). Each ray stays uniform over
// its sub-square, so over the scramble every ray is uniform over the square: a node's mean
// is unbiased and the box mean of a whole tile is an L-level stratified estimate. L = 0 is
// the whole square at every cell.

#include <cstdint>

#include "bake/transport/final_gather.h"

namespace lb {

// Largest number of levels: 16 x 16 sub-squares, a tile wider than the widest correction box.
inline constexpr int kMaxStrataLevels = 4;

// The sub-square of cell (cell_x, cell_y) >= 0 at `levels` in [0, kMaxStrataLevels].
SampleCell interleaved_stratum(int cell_x, int cell_y, int levels, uint64_t scramble);

}  // namespace lb
