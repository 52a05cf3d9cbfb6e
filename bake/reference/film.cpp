#include "bake/reference/film.h"

#include <cmath>

namespace lb::reference {

Film::Film(int w, int h) : width(w), height(h) {
  for (auto& h_sum : half) h_sum.assign(size_t(w) * size_t(h), glm::dvec3(0.0));
}

void Film::add_pass(const std::vector<vec3>& pass) {
  const int which = passes() % 2;
  std::vector<glm::dvec3>& sum = half[which];
  double mean = 0.0;
  for (size_t i = 0; i < sum.size(); ++i) {
    sum[i] += glm::dvec3(pass[i]);
    mean += (double(pass[i].x) + double(pass[i].y) + double(pass[i].z)) / 3.0;
  }
  pass_means.push_back(sum.empty() ? 0.0 : mean / double(sum.size()));
  ++half_passes[which];
}

std::vector<vec3> Film::average() const {
  std::vector<vec3> image(half[0].size(), vec3(0.0f));
  if (passes() == 0) return image;
  for (size_t i = 0; i < image.size(); ++i)
    image[i] = vec3((half[0][i] + half[1][i]) / double(passes()));
  return image;
}

std::vector<vec3> Film::half_average(int which) const {
  if (half_passes[which] == 0) return {};
  std::vector<vec3> image(half[which].size());
  for (size_t i = 0; i < image.size(); ++i)
    image[i] = vec3(half[which][i] / double(half_passes[which]));
  return image;
}

NoiseEstimate Film::noise() const {
  NoiseEstimate noise;
  if (half_passes[0] == 0 || half_passes[1] == 0 || half[0].empty()) return noise;
  auto grey = [](glm::dvec3 v) { return (v.x + v.y + v.z) / 3.0; };
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
