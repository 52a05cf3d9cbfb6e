#include "bake/sky_light.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "bake/constants.h"

namespace lb {

namespace {

// Index of the first cdf entry above u (the strata are [cdf[i-1], cdf[i])), and u rescaled to
// [0,1) inside it.
size_t pick(const float* cdf, size_t n, float& u) {
  const size_t i = std::min(size_t(std::upper_bound(cdf, cdf + n, u) - cdf), n - 1);
  const float lo = i == 0 ? 0.0f : cdf[i - 1];
  const float width = cdf[i] - lo;
  u = width > 0.0f ? std::clamp((u - lo) / width, 0.0f, 0.99999994f) : 0.5f;
  return i;
}
}  // namespace

vec2 direction_to_equirect(vec3 d) {
  const float u = 0.5f + std::atan2(d.x, -d.z) / (2.0f * kPi);
  const float v = std::acos(std::clamp(d.y, -1.0f, 1.0f)) / kPi;
  return {u - std::floor(u), v};
}

vec3 equirect_to_direction(vec2 uv) {
  const float phi = (uv.x - 0.5f) * 2.0f * kPi;
  const float theta = uv.y * kPi;
  const float s = std::sin(theta);
  return {s * std::sin(phi), std::cos(theta), -s * std::cos(phi)};
}

SkyLight::SkyLight(const Sky& sky, const Texture* image) : radiance_(sky.radiance) {
  if (image && image->width > 0 && image->height > 0 && !image->texels.empty()) {
    image_ = image;
    width_ = image->width;
    height_ = image->height;
  }
  if (!image_) {
    integral_ = 4.0f * kPi * radiance_;
    return;
  }
  // Texel (i, j) spans dphi = 2 pi / w and theta in [j, j+1] pi / h: solid angle
  // dphi * (cos theta0 - cos theta1).
  const size_t w = size_t(width_), h = size_t(height_);
  texel_pdf_.resize(w * h);
  column_cdf_.resize(w * h);
  row_cdf_.resize(h);
  double total = 0.0;
  glm::dvec3 integral(0.0);
  for (size_t j = 0; j < h; ++j) {
    const double solid_angle = 2.0 * std::numbers::pi / double(w) *
                               (std::cos(std::numbers::pi * double(j) / double(h)) -
                                std::cos(std::numbers::pi * double(j + 1) / double(h)));
    double row = 0.0;
    for (size_t i = 0; i < w; ++i) {
      const vec3 l = texel(int(i), int(j));
      integral += solid_angle * glm::dvec3(l);
      const double weight = double(std::max(luminance(l), 0.0f)) * solid_angle;
      texel_pdf_[j * w + i] = float(weight);
      row += weight;
      column_cdf_[j * w + i] = float(row);
    }
    for (size_t i = 0; i < w; ++i)
      column_cdf_[j * w + i] =
          row > 0.0 ? float(column_cdf_[j * w + i] / row) : float(i + 1) / float(w);
    column_cdf_[j * w + w - 1] = 1.0f;
    total += row;
    row_cdf_[j] = float(total);
  }
  integral_ = vec3(integral);
  if (!(total > 0.0)) {  // a black image: draw uniformly, nothing will come of it
    image_ = nullptr;
    integral_ = vec3(0.0f);
    radiance_ = vec3(0.0f);
    return;
  }
  for (float& c : row_cdf_) c = float(c / total);
  row_cdf_.back() = 1.0f;
  for (float& p : texel_pdf_) p = float(p / total);
}

vec3 SkyLight::texel(int column, int row) const {
  const size_t index = (size_t(row) * size_t(width_) + size_t(column)) * size_t(image_->channels);
  const float* t = &image_->texels[index];
  const vec3 c = image_->channels >= 3 ? vec3(t[0], t[1], t[2]) : vec3(t[0]);
  return radiance_ * c;
}

vec3 SkyLight::radiance(vec3 to_sky) const {
  if (!image_) return radiance_;
  const vec2 uv = direction_to_equirect(to_sky);
  const int i = std::clamp(int(uv.x * float(width_)), 0, width_ - 1);
  const int j = std::clamp(int(uv.y * float(height_)), 0, height_ - 1);
  return texel(i, j);
}

vec3 SkyLight::sample(vec2 u, float& pdf) const {
  if (!image_) {
    const float z = 1.0f - 2.0f * u.x;
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    const float phi = 2.0f * kPi * u.y;
    pdf = 1.0f / (4.0f * kPi);
    return {r * std::cos(phi), z, r * std::sin(phi)};
  }
  float uy = u.y, ux = u.x;
  const size_t j = pick(row_cdf_.data(), row_cdf_.size(), uy);
  const size_t i = pick(&column_cdf_[j * size_t(width_)], size_t(width_), ux);
  // Uniform in solid angle inside the texel: phi linear, cos(theta) linear.
  const float c0 = std::cos(kPi * float(j) / float(height_));
  const float c1 = std::cos(kPi * float(j + 1) / float(height_));
  const float cos_theta = c0 + uy * (c1 - c0);
  const float u_phi = (float(i) + ux) / float(width_);
  const float sin_theta = std::sqrt(std::max(0.0f, 1.0f - cos_theta * cos_theta));
  const float phi = (u_phi - 0.5f) * 2.0f * kPi;
  const vec3 d{sin_theta * std::sin(phi), cos_theta, -sin_theta * std::cos(phi)};
  const float solid_angle = 2.0f * kPi / float(width_) * (c0 - c1);
  pdf = texel_pdf_[j * size_t(width_) + i] / solid_angle;
  return d;
}

float SkyLight::pdf(vec3 to_sky) const {
  if (!image_) return 1.0f / (4.0f * kPi);
  const vec2 uv = direction_to_equirect(to_sky);
  const int i = std::clamp(int(uv.x * float(width_)), 0, width_ - 1);
  const int j = std::clamp(int(uv.y * float(height_)), 0, height_ - 1);
  const float c0 = std::cos(kPi * float(j) / float(height_));
  const float c1 = std::cos(kPi * float(j + 1) / float(height_));
  const float solid_angle = 2.0f * kPi / float(width_) * (c0 - c1);
  return texel_pdf_[size_t(j) * size_t(width_) + size_t(i)] / solid_angle;
}

}  // namespace lb
