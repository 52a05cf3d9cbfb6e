#pragma once
// The reference renderer's accumulation buffer and its own noise estimate.
//
// Every pass is one independent, unbiased estimate of the whole image (one eye path per pixel
// plus the light-tracing splats of that pass). Even passes go to half 0, odd passes to half 1,
// so the two halves are independent estimates and their difference measures the noise:
// for a pixel with halves a and b over the same number of passes, the variance of the mean
// (a + b) / 2 is estimated without bias by (a - b)^2 / 4.

#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "bake/scene.h"

namespace lb::reference {

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
  std::vector<glm::dvec3> half[2];  // sums of passes, W/(sr m^2) x passes
  int half_passes[2] = {0, 0};
  std::vector<double> pass_means;  // per pass, mean over pixels of the RGB mean, W/(sr m^2)

  Film() = default;
  Film(int w, int h);
  int passes() const { return half_passes[0] + half_passes[1]; }
  // Adds one pass's estimate (width x height values, row 0 at the top).
  void add_pass(const std::vector<vec3>& pass);
  std::vector<vec3> average() const;  // radiance per pixel, W/(sr m^2)
  // The two halves' averages (for noise maps and tests); empty while a half has no pass.
  std::vector<vec3> half_average(int which) const;
  NoiseEstimate noise() const;
};

}  // namespace lb::reference
