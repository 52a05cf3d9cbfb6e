#pragma once
// The reference renderer's accumulation buffer and its own noise estimate.
//
// Every pass is one independent, unbiased estimate of the whole image (one eye path per pixel
// plus the light-tracing splats of that pass). Even passes go to half 0, odd passes to half 1,
// so the two halves are independent estimates and their difference measures the noise:
// for a pixel with halves a and b over the same number of passes, the variance of the mean
// (a + b) / 2 is estimated without bias by (a - b)^2 / 4.
//
// ---- Sums in fixed point (issue 16: shards of passes add in any order) ------------------
// A pass's value per pixel and channel (a float, W/(sr m^2)) is added as an integer number of
// units of 2^-kFixedFractionBits = 2^-60 W/(sr m^2) to a 128-bit accumulator. Integer sums
// do not depend on the order of the adds, so a film rendered in shards of passes and summed
// (Film::add) has the bits of the film rendered in one go.
//  - Exact: a float of magnitude >= 2^-37 (7.3e-12 W/(sr m^2)) is a multiple of 2^-60, so it
//    is added without rounding; smaller values round to the nearest unit, 8.7e-19 W/(sr m^2)
//    at most per add, far below any radiance a scene shows (the bundled scenes' pixels are
//    1e-3 to 1e2 W/(sr m^2); the sun's disc about 2e7).
//  - Range: a pass value must be below 2^kMaxValueBits = 2^36 = 6.9e10 W/(sr m^2) (3000x the
//    sun's radiance) and the passes are at most 2^31 (ReferenceParams::spp is an int), so a sum
//    stays below 2^(36 + 31 + 60) = 2^127 units: an int128 cannot overflow. A pixel's value
//    that is not finite or beyond the bound is a lost sample (counted, added as 0), as a
//    non-finite one always was.

#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "bake/scene.h"

namespace lb::reference {

inline constexpr int kFixedFractionBits = 60;
inline constexpr int kMaxValueBits = 36;

using FixedSum = __int128;  // units of 2^-kFixedFractionBits W/(sr m^2) x passes

struct FixedPixel {
  FixedSum c[3] = {0, 0, 0};
};

struct NoiseEstimate {
  // sqrt(mean over pixels of (a - b)^2 / 4) / (mean pixel value), on the RGB mean: the typical
  // per-pixel standard error relative to the image's mean brightness. 0 before two passes.
  double pixel_relative_standard_error = 0.0;
  // Standard error of the image's mean value relative to that mean, from the spread of the
  // per-pass image means (sample standard deviation / sqrt(passes)). 0 before two passes.
  double mean_relative_standard_error = 0.0;
};

struct Film {
  int width = 0;
  int height = 0;
  std::vector<FixedPixel> half[2];  // sums of passes
  int half_passes[2] = {0, 0};
  // Per pass, in increasing pass index: the index and the mean over pixels of the RGB mean,
  // W/(sr m^2) (a shard holds only its own passes).
  std::vector<uint64_t> pass_indices;
  std::vector<double> pass_means;
  uint64_t lost_samples = 0;  // pixel values not finite or >= 2^kMaxValueBits, added as 0

  Film() = default;
  Film(int w, int h);
  int passes() const { return half_passes[0] + half_passes[1]; }
  // Adds pass `pass`'s estimate (width x height values, row 0 at the top) to half pass % 2.
  // Passes may come in any order; a pass index given twice throws std::invalid_argument.
  void add_pass(uint64_t pass, const std::vector<vec3>& estimate);
  // Adds another film's passes (a shard's): same size and no pass in common, else throws
  // std::invalid_argument. The result has the bits of the film that rendered all the passes.
  void add(const Film& other);
  std::vector<vec3> average() const;  // radiance per pixel, W/(sr m^2)
  // The two halves' averages (for noise maps and tests); empty while a half has no pass.
  std::vector<vec3> half_average(int which) const;
  NoiseEstimate noise() const;
};

// A radiance in fixed-point units (rounded to the nearest), and back.
FixedSum to_fixed_radiance(float value);
double from_fixed_radiance(FixedSum units);

}  // namespace lb::reference
