#include "bake/lightmap/interleaved_strata.h"

namespace lb {

namespace {

// The low `bits` bits of v in reverse order.
uint32_t reverse_bits(uint32_t v, int bits) {
  uint32_t r = 0;
  for (int b = 0; b < bits; ++b) r |= ((v >> b) & 1u) << (bits - 1 - b);
  return r;
}

}  // namespace

SampleCell interleaved_stratum(int cell_x, int cell_y, int levels, uint64_t scramble) {
  if (levels <= 0) return {};
  const uint32_t side = 1u << levels, mask = side - 1u;
  const uint32_t sx = reverse_bits(uint32_t(cell_x) & mask, levels) ^ (uint32_t(scramble) & mask);
  const uint32_t sy =
      reverse_bits(uint32_t(cell_y) & mask, levels) ^ (uint32_t(scramble >> 32) & mask);
  const float size = 1.0f / float(side);
  return {vec2(float(sx), float(sy)) * size, vec2(size)};
}

}  // namespace lb
