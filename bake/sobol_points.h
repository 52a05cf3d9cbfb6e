#pragma once
// A progressive stratification: the first four dimensions of Sobol's sequence (Sobol 1967),
// with a random digital shift. Its first two dimensions are a (0,2)-sequence in base 2.
//
// Why: a pixel of HQ mode gathers over many passes of N x N samples. Jittered strata drawn
// afresh each pass stratify only within a pass (16 strata at 16 spp, again and again); the
// points of a (0,2)-sequence stratify every block of 2^m consecutive points starting at a
// multiple of 2^m into all 2^a x 2^b boxes with a + b = m, so pass k's 16 points form a 4 x 4
// grid and passes 0..15 together a 16 x 16 one, however many passes there are. Dimensions 2
// and 3 draw a second 2D sample stratified jointly with the first (the light point at the
// gather ray's hit), better than a random pairing of two stratified sets.
//
// The shift XORs a per-pixel 32-bit key into each coordinate's binary digits (a digital shift,
// Owen 1995 / L'Ecuyer): it permutes the boxes of every level, so the stratification holds,
// and over a uniformly random key each point is uniform on the square: estimates stay unbiased.

#include <cstdint>

#include <glm/glm.hpp>

namespace lb {

// Sobol's direction numbers of dimensions 1..3 (the primitive polynomials x + 1, x^2 + x + 1
// and x^3 + x + 1 with initial numbers {1}, {1, 3} and {1, 3, 1}, as Joe and Kuo 2008 list
// them), as 32-bit binary fractions v_k = m_k / 2^k, from the recurrence
//   m_k = 2 a_1 m_{k-1} ^ 4 a_2 m_{k-2} ^ ... ^ 2^s m_{k-s} ^ m_{k-s}.
// With them, per dimension and byte of the index, the XOR of the direction numbers of each
// byte value's set bits: a coordinate is four lookups (12 KiB of tables).
struct SobolDirections {
  uint32_t v[3][32] = {};
  uint32_t byte_xor[3][4][256] = {};
  constexpr SobolDirections() {
    constexpr int degree[3] = {1, 2, 3};
    constexpr uint32_t inner[3] = {0, 1, 1};  // a_1 .. a_{s-1}, a_1 the highest bit
    constexpr uint32_t initial[3][3] = {{1, 0, 0}, {1, 3, 0}, {1, 3, 1}};
    for (int d = 0; d < 3; ++d) {
      const int s = degree[d];
      uint32_t m[33] = {};
      for (int k = 1; k <= 32; ++k) {
        if (k <= s) {
          m[k] = initial[d][k - 1];
        } else {
          m[k] = m[k - s] ^ (m[k - s] << s);
          for (int i = 1; i < s; ++i)
            if ((inner[d] >> (s - 1 - i)) & 1u) m[k] ^= m[k - i] << i;
        }
        v[d][k - 1] = m[k] << (32 - k);
      }
      for (int byte = 0; byte < 4; ++byte)
        for (uint32_t value = 1; value < 256; ++value) {
          int lowest = 0;  // the value's lowest set bit: the value is that bit and the rest
          while (!((value >> lowest) & 1u)) ++lowest;
          byte_xor[d][byte][value] =
              byte_xor[d][byte][value & (value - 1)] ^ v[d][8 * byte + lowest];
        }
    }
  }
};
inline constexpr SobolDirections kSobolDirections{};

// Coordinate `dimension` in [0, 3] of point `index`, as 32 bits of binary fraction.
// Dimension 0 is the van der Corput radical inverse (the bits reversed).
inline uint32_t sobol_coordinate(uint32_t index, int dimension) {
  if (dimension == 0) {
    index = (index << 16) | (index >> 16);
    index = ((index & 0x00ff00ffu) << 8) | ((index & 0xff00ff00u) >> 8);
    index = ((index & 0x0f0f0f0fu) << 4) | ((index & 0xf0f0f0f0u) >> 4);
    index = ((index & 0x33333333u) << 2) | ((index & 0xccccccccu) >> 2);
    return ((index & 0x55555555u) << 1) | ((index & 0xaaaaaaaau) >> 1);
  }
  // Table lookups: a branch on each of the index's bits, as good as random, was mispredicted
  // often enough to cost HQ mode a quarter of its time.
  const auto& table = kSobolDirections.byte_xor[dimension - 1];
  return table[0][index & 0xffu] ^ table[1][(index >> 8) & 0xffu] ^
         table[2][(index >> 16) & 0xffu] ^ table[3][index >> 24];
}

// Dimensions (first, first + 1) of point `index`, each coordinate's digits XORed by its half
// of `shift`, in [0, 1)^2 (24 bits a coordinate, as Rng::next_float).
inline glm::vec2 shifted_sobol_point(uint32_t index, uint64_t shift, int first = 0) {
  const uint32_t x = sobol_coordinate(index, first) ^ uint32_t(shift);
  const uint32_t y = sobol_coordinate(index, first + 1) ^ uint32_t(shift >> 32);
  return {float(x >> 8) * 0x1p-24f, float(y >> 8) * 0x1p-24f};
}

}  // namespace lb
