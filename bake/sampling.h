#pragma once
// Random numbers and the square-to-X maps of the paper's Figure 2.
// Everything is deterministic: a generator is seeded from (seed, stream) so that the
// same work item draws the same numbers whatever thread runs it.

#include <cmath>
#include <cstddef>
#include <cstdint>

#include <glm/glm.hpp>

namespace lb {

// PCG32 (O'Neill 2014): small state, good statistics, independent streams. Inline: every
// pass draws several numbers per ray.
class Rng {
 public:
  explicit Rng(uint64_t seed = 0x853c49e6748fea9bULL, uint64_t stream = 0xda3e39cb94b95bdbULL);
  uint32_t next_u32() {
    const uint64_t old = state_;
    state_ = old * 6364136223846793005ULL + inc_;
    const uint32_t xorshifted = uint32_t(((old >> 18u) ^ old) >> 27u);
    const uint32_t rot = uint32_t(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((~rot + 1u) & 31u));
  }
  // Uniform in [0, 1): 24 random mantissa bits, exactly representable, strictly below 1.
  float next_float() { return float(next_u32() >> 8) * 0x1p-24f; }
  glm::vec2 next_2d() { float a = next_float(); return {a, next_float()}; }

 private:
  uint64_t state_ = 0;
  uint64_t inc_ = 0;
};

// Russian roulette on `throughput` (max channel m): below `threshold` the path survives with
// probability m / threshold (then throughput is divided by it, keeping the estimate unbiased);
// true if the path goes on, false also when nothing is left. `u` uniform in [0, 1).
bool survive_roulette(glm::vec3& throughput, float threshold, float u);
// The same, drawing u from `rng` only when the roulette is played.
bool survive_roulette(glm::vec3& throughput, float threshold, Rng& rng);

// splitmix64's finaliser: 64 well-mixed bits from any 64 (also a counter-based generator).
inline uint64_t mix64(uint64_t z) {
  z += 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

// Mixes several integers into one well-spread seed.
inline uint64_t hash_seed(uint64_t a, uint64_t b = 0, uint64_t c = 0) {
  return mix64(a ^ mix64(b ^ mix64(c)));
}

// Shirley-Chiu concentric map: a partitioned square maps to a partitioned disk with zones
// that stay compact (the right-hand disk of Figure 2). u in [0,1]^2 -> unit disk.
glm::vec2 square_to_disk(glm::vec2 u);

namespace detail {
// sin and cos on [-pi/4, pi/4] by their Taylor series to a^9 and a^10: error below 3e-9,
// under float's rounding. Coefficients are products: a division by a constant that is not a
// power of two stays a division.
inline void sin_cos_quarter(float a, float& s, float& c) {
  constexpr float s3 = float(-1.0 / 6), s5 = float(1.0 / 120), s7 = float(-1.0 / 5040),
                  s9 = float(1.0 / 362880);
  constexpr float c2 = -0.5f, c4 = float(1.0 / 24), c6 = float(-1.0 / 720),
                  c8 = float(1.0 / 40320), c10 = float(-1.0 / 3628800);
  const float a2 = a * a;
  s = a * (1.0f + a2 * (s3 + a2 * (s5 + a2 * (s7 + a2 * s9))));
  c = 1.0f + a2 * (c2 + a2 * (c4 + a2 * (c6 + a2 * (c8 + a2 * c10))));
}
}  // namespace detail

// Cosine-weighted hemisphere about +z through the concentric disk (Malley's method):
// square_to_disk lifted to the hemisphere, pdf = cos(theta) / pi. Inline and branch-free
// (octant by selects, polynomial sin/cos: within 1e-6 of square_to_disk's sincosf, tested),
// because every pass draws one per ray; compilers vectorise it without errno or traps.
inline glm::vec3 square_to_cosine_hemisphere(glm::vec2 u) {
  const float x = 2.0f * u.x - 1.0f, y = 2.0f * u.y - 1.0f;
  const bool x_major = std::abs(x) > std::abs(y);
  const float r = x_major ? x : y;  // |r| >= the other: 0 only at the centre
  const float other = x_major ? y : x;
  const float ratio = other / (r != 0.0f ? r : 1.0f);
  float s, c;
  detail::sin_cos_quarter(0.78539816f * ratio, s, c);
  // x major: theta = a, (cos, sin); else theta = pi/2 - a, (sin, cos).
  const float dx = r * (x_major ? c : s), dy = r * (x_major ? s : c);
  const float z2 = 1.0f - dx * dx - dy * dy;
  return {dx, dy, std::sqrt(z2 > 0.0f ? z2 : 0.0f)};
}

// Uniform point on a triangle from u in [0,1]^2, returned as barycentrics (b1, b2) (Heitz
// 2019: area-preserving, low distortion, keeps strata compact). Branch-free, inline.
inline glm::vec2 square_to_triangle(glm::vec2 u) {
  const bool upper = u.y > u.x;
  const float half = 0.5f * (upper ? u.x : u.y);
  const float b0 = upper ? half : u.x - half;
  const float b1 = upper ? u.y - half : half;
  return {b1, 1.0f - b0 - b1};
}

// The first i in [0, count) where `before(i)` is false (count if none), for a `before` that
// holds on a prefix and fails after it (`cdf[i] < u` on a CDF): std::lower_bound's and
// std::upper_bound's answer, with a number of probes fixed by `count` and a conditional move
// for each, where a sampled u mispredicts the std:: versions' branches half the time.
template <class Before>
inline size_t partition_point_index(size_t count, Before before) {
  if (count == 0) return 0;
  size_t base = 0;
  while (count > 1) {
    const size_t half = count / 2;
    base = before(base + half) ? base + half : base;
    count -= half;
  }
  return base + (before(base) ? 1 : 0);
}

// Stratum (i, j) of an n x m grid over the unit square, jittered by `jitter` in [0,1)^2.
inline glm::vec2 stratified(int i, int j, int n, int m, glm::vec2 jitter) {
  return {(float(i) + jitter.x) / float(n), (float(j) + jitter.y) / float(m)};
}

// An orthonormal basis around unit n (Duff et al. 2017, branchless).
struct Frame {
  glm::vec3 tangent, bitangent, normal;
  explicit Frame(glm::vec3 n);
  glm::vec3 to_world(glm::vec3 local) const {
    return tangent * local.x + bitangent * local.y + normal * local.z;
  }
  glm::vec3 to_local(glm::vec3 world) const {
    return {glm::dot(world, tangent), glm::dot(world, bitangent), glm::dot(world, normal)};
  }
};

}  // namespace lb
