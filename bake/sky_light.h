#pragma once
// The sky as a light: radiance by direction and directions drawn in proportion to it.
// A constant sky draws uniformly over the sphere; an equirect image draws a texel in
// proportion to its luminance times its solid angle, then a direction uniformly inside it
// (so radiance() looks texels up without filtering: the density matches what is returned).

#include <vector>

#include "bake/scene.h"

namespace lb {

class SkyLight {
 public:
  // `sky` must outlive this; `image` is the equirect texture or nullptr.
  SkyLight(const Sky& sky, const Texture* image);

  // Radiance arriving from unit direction `to_sky` (scene -> sky), W/(sr m^2).
  vec3 radiance(vec3 to_sky) const;
  // A direction towards the sky from u in [0,1)^2, and its solid-angle density.
  vec3 sample(vec2 u, float& pdf) const;
  float pdf(vec3 to_sky) const;
  // The integral of radiance over the sphere, W/(m^2) per channel: what a unit disk facing
  // every direction in turn would receive, so pi R^2 times it crosses a disk of radius R.
  vec3 integral() const { return integral_; }

 private:
  vec3 texel(int column, int row) const;

  vec3 radiance_{0.0f};
  const Texture* image_ = nullptr;
  int width_ = 0, height_ = 0;
  std::vector<float> row_cdf_;     // height_ entries, last 1
  std::vector<float> column_cdf_;  // width_ * height_, per row, last of each 1
  std::vector<float> texel_pdf_;   // probability of each texel (sums to 1)
  vec3 integral_{0.0f};
};

// Equirect image coordinates (u, v) in [0,1]^2 of unit direction d, and back.
vec2 direction_to_equirect(vec3 d);
vec3 equirect_to_direction(vec2 uv);

}  // namespace lb
