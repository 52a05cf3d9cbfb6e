#include "bake/reference/film.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace lb::reference {

namespace {

double grey(const FixedPixel& p) {
  return (from_fixed_radiance(p.c[0]) + from_fixed_radiance(p.c[1]) + from_fixed_radiance(p.c[2])) /
         3.0;
}

bool representable(vec3 v) {
  const float bound = std::ldexp(1.0f, kMaxValueBits);
  for (int c = 0; c < 3; ++c)
    if (!std::isfinite(v[c]) || std::abs(v[c]) >= bound) return false;
  return true;
}

// Where pass `pass` goes in the sorted list; throws if it is there already.
size_t insertion_point(const std::vector<uint64_t>& indices, uint64_t pass) {
  const auto at = std::lower_bound(indices.begin(), indices.end(), pass);
  if (at != indices.end() && *at == pass)
    throw std::invalid_argument("film: pass " + std::to_string(pass) + " added twice");
  return size_t(at - indices.begin());
}

}  // namespace

FixedSum to_fixed_radiance(float value) {
  // |value| < 2^36: the scaled value is below 2^96, exact in a double when value >= 2^-37.
  return FixedSum(std::nearbyint(std::ldexp(double(value), kFixedFractionBits)));
}

double from_fixed_radiance(FixedSum units) {
  return std::ldexp(double(units), -kFixedFractionBits);
}

Film::Film(int w, int h) : width(w), height(h) {
  for (auto& h_sum : half) h_sum.assign(size_t(w) * size_t(h), FixedPixel{});
}

void Film::add_pass(uint64_t pass, const std::vector<vec3>& estimate) {
  const size_t at = insertion_point(pass_indices, pass);
  const int which = int(pass % 2);
  std::vector<FixedPixel>& sum = half[which];
  double mean = 0.0;
  for (size_t i = 0; i < sum.size(); ++i) {
    const vec3 v = estimate[i];
    if (!representable(v)) {
      ++lost_samples;
      continue;
    }
    for (int c = 0; c < 3; ++c) sum[i].c[c] += to_fixed_radiance(v[c]);
    mean += (double(v.x) + double(v.y) + double(v.z)) / 3.0;
  }
  pass_indices.insert(pass_indices.begin() + std::ptrdiff_t(at), pass);
  pass_means.insert(pass_means.begin() + std::ptrdiff_t(at),
                    sum.empty() ? 0.0 : mean / double(sum.size()));
  ++half_passes[which];
}

void Film::add(const Film& other) {
  if (other.width != width || other.height != height)
    throw std::invalid_argument("film: adding a " + std::to_string(other.width) + "x" +
                                std::to_string(other.height) + " film to a " +
                                std::to_string(width) + "x" + std::to_string(height) + " one");
  for (uint64_t pass : other.pass_indices) insertion_point(pass_indices, pass);  // none shared
  for (int h = 0; h < 2; ++h) {
    if (other.half_passes[h] == 0) continue;
    for (size_t i = 0; i < half[h].size(); ++i)
      for (int c = 0; c < 3; ++c)
        // Only corrupt data can overflow (see the range above); refuse it rather than wrap.
        if (__builtin_add_overflow(half[h][i].c[c], other.half[h][i].c[c], &half[h][i].c[c]))
          throw std::invalid_argument("film: a pixel sum overflows 128 bits");
    half_passes[h] += other.half_passes[h];
  }
  for (size_t k = 0; k < other.pass_indices.size(); ++k) {
    const size_t at = insertion_point(pass_indices, other.pass_indices[k]);
    pass_indices.insert(pass_indices.begin() + std::ptrdiff_t(at), other.pass_indices[k]);
    pass_means.insert(pass_means.begin() + std::ptrdiff_t(at), other.pass_means[k]);
  }
  lost_samples += other.lost_samples;
}

std::vector<vec3> Film::average() const {
  std::vector<vec3> image(half[0].size(), vec3(0.0f));
  if (passes() == 0) return image;
  for (size_t i = 0; i < image.size(); ++i)
    for (int c = 0; c < 3; ++c)
      image[i][c] = float(from_fixed_radiance(half[0][i].c[c] + half[1][i].c[c]) / passes());
  return image;
}

std::vector<vec3> Film::half_average(int which) const {
  if (half_passes[which] == 0) return {};
  std::vector<vec3> image(half[which].size());
  for (size_t i = 0; i < image.size(); ++i)
    for (int c = 0; c < 3; ++c)
      image[i][c] = float(from_fixed_radiance(half[which][i].c[c]) / half_passes[which]);
  return image;
}

NoiseEstimate Film::noise() const {
  NoiseEstimate noise;
  if (half_passes[0] == 0 || half_passes[1] == 0 || half[0].empty()) return noise;
  double squared = 0.0, mean = 0.0;
  for (size_t i = 0; i < half[0].size(); ++i) {
    const double a = grey(half[0][i]) / half_passes[0], b = grey(half[1][i]) / half_passes[1];
    // With unequal halves (an odd pass count) the variance of the pooled mean is weighted:
    // var(a - b) = s2 (1/n0 + 1/n1), var(pooled) = s2 / (n0 + n1).
    const double n0 = half_passes[0], n1 = half_passes[1];
    squared += (a - b) * (a - b) / ((1.0 / n0 + 1.0 / n1) * (n0 + n1));
    mean += (n0 * a + n1 * b) / (n0 + n1);
  }
  const double pixels = double(half[0].size());
  mean /= pixels;
  if (mean > 0.0) noise.pixel_relative_standard_error = std::sqrt(squared / pixels) / mean;

  const double n = double(pass_means.size());
  double m = 0.0, m2 = 0.0;
  for (double v : pass_means) m += v;
  m /= n;
  for (double v : pass_means) m2 += (v - m) * (v - m);
  if (m > 0.0) noise.mean_relative_standard_error = std::sqrt(m2 / (n - 1.0) / n) / m;
  return noise;
}

}  // namespace lb::reference
