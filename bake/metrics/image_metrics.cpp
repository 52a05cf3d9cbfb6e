#include "bake/metrics/image_metrics.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <vector>

#include <nlohmann/json.hpp>

#include "bake/json_text.h"

namespace lb {

namespace {

int colour_channels(const Image& image) { return std::min(image.channels, 3); }

std::string size_text(const Image& image) {
  return std::to_string(image.width) + "x" + std::to_string(image.height);
}

void require_comparable(const Image& a, const Image& b) {
  if (a.width != b.width || a.height != b.height)
    throw std::invalid_argument("B: size " + size_text(b) + " differs from A's " + size_text(a));
  if (colour_channels(a) != colour_channels(b))
    throw std::invalid_argument("B: " + std::to_string(colour_channels(b)) +
                                " colour channels, A has " + std::to_string(colour_channels(a)));
}

// The compared pixels as a predicate over (x, y), after checking the region and the mask.
struct Selection {
  PixelRegion box;
  const Image* mask = nullptr;
  bool contains(int x, int y) const {
    return x >= box.x0 && x < box.x1 && y >= box.y0 && y < box.y1 &&
           (mask == nullptr || mask->at(x, y, 0) > 0.5f);
  }
};

Selection make_selection(const Image& image, const CompareParams& params) {
  Selection selection;
  selection.box = params.region;
  if (params.region.whole()) {
    selection.box = {0, 0, image.width, image.height};
  } else if (params.region.x0 < 0 || params.region.y0 < 0 || params.region.x1 > image.width ||
             params.region.y1 > image.height) {
    const PixelRegion& r = params.region;
    throw std::invalid_argument("region " + std::to_string(r.x0) + "," + std::to_string(r.y0) +
                                "," + std::to_string(r.x1) + "," + std::to_string(r.y1) +
                                " lies outside the " + size_text(image) + " image");
  }
  if (params.mask != nullptr) {
    if (params.mask->width != image.width || params.mask->height != image.height)
      throw std::invalid_argument("mask: size " + size_text(*params.mask) + " differs from A's " +
                                  size_text(image));
    selection.mask = params.mask;
  }
  return selection;
}

}  // namespace

ImageMetrics compare_to_reference(const Image& image, const Image& reference,
                                  const CompareParams& params) {
  require_comparable(image, reference);
  const Selection selection = make_selection(image, params);
  ImageMetrics m;
  m.channels = colour_channels(image);
  std::array<double, 3> sum_a{}, sum_b{};
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      if (!selection.contains(x, y)) continue;
      ++m.pixels;
      for (int c = 0; c < m.channels; ++c) {
        sum_a[size_t(c)] += image.at(x, y, c);
        sum_b[size_t(c)] += reference.at(x, y, c);
      }
    }
  if (m.pixels == 0) throw std::invalid_argument("no pixel left to compare (region and mask)");
  const double values = double(m.pixels) * double(m.channels);
  double total_a = 0.0, total_b = 0.0;
  for (int c = 0; c < m.channels; ++c) {
    total_a += sum_a[size_t(c)];
    total_b += sum_b[size_t(c)];
    m.sum_ratio[size_t(c)] = sum_a[size_t(c)] / sum_b[size_t(c)];
  }
  m.sum_ratio_total = total_a / total_b;
  m.mean_reference = total_b / values;
  m.epsilon = params.epsilon > 0.0 ? params.epsilon
                                   : params.epsilon_fraction * std::abs(m.mean_reference);

  const double eps = m.epsilon;
  double relative = 0.0, relative_squared = 0.0, squared = 0.0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      if (!selection.contains(x, y)) continue;
      for (int c = 0; c < m.channels; ++c) {
        const double a = image.at(x, y, c), b = reference.at(x, y, c);
        const double d = a - b;
        const float fa = image.at(x, y, c), fb = reference.at(x, y, c);
        m.differing_values += std::memcmp(&fa, &fb, sizeof(float)) != 0;
        relative += std::abs(d) / (std::abs(b) + eps);
        relative_squared += d * d / (b * b + eps * eps);
        squared += d * d;
      }
    }
  m.mean_relative_error = relative / values;
  m.relative_mse = relative_squared / values;
  m.rmse = std::sqrt(squared / values);
  return m;
}

std::string metrics_json(const ImageMetrics& m) {
  nlohmann::ordered_json j;
  j["mre"] = m.mean_relative_error;
  j["relmse"] = m.relative_mse;
  j["rmse"] = m.rmse;
  j["sum_ratio"] = std::vector<double>(m.sum_ratio.begin(), m.sum_ratio.begin() + m.channels);
  j["sum_ratio_total"] = m.sum_ratio_total;
  j["epsilon"] = m.epsilon;
  j["mean_reference"] = m.mean_reference;
  j["pixels"] = m.pixels;
  j["channels"] = m.channels;
  j["differing_values"] = m.differing_values;
  return json_text(j);
}

Image relative_error_image(const Image& image, const Image& reference, const CompareParams& params,
                           double epsilon) {
  require_comparable(image, reference);
  const Selection selection = make_selection(image, params);
  const int channels = colour_channels(image);
  Image error(image.width, image.height, 1, -1.0f);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      if (!selection.contains(x, y)) continue;
      double sum = 0.0;
      for (int c = 0; c < channels; ++c) {
        const double b = reference.at(x, y, c);
        sum += std::abs(image.at(x, y, c) - b) / (std::abs(b) + epsilon);
      }
      error.at(x, y) = float(sum / channels);
    }
  return error;
}

Image subtract_images(const Image& minuend, const Image& subtrahend) {
  require_comparable(minuend, subtrahend);
  Image difference = minuend;
  const int channels = colour_channels(minuend);
  for (int y = 0; y < minuend.height; ++y)
    for (int x = 0; x < minuend.width; ++x)
      for (int c = 0; c < channels; ++c) difference.at(x, y, c) -= subtrahend.at(x, y, c);
  return difference;
}

PixelRegion parse_region(const std::string& text) {
  PixelRegion r;
  int* fields[] = {&r.x0, &r.y0, &r.x1, &r.y1};
  size_t start = 0;
  try {
    for (int i = 0; i < 4; ++i) {
      const size_t end = i < 3 ? text.find(',', start) : text.size();
      if (end == std::string::npos) throw std::invalid_argument("");
      size_t used = 0;
      *fields[i] = std::stoi(text.substr(start, end - start), &used);
      if (used != end - start) throw std::invalid_argument("");
      start = end + 1;
    }
  } catch (const std::exception&) {
    throw std::invalid_argument("--region '" + text + "': expected x0,y0,x1,y1 in pixels");
  }
  if (r.x1 <= r.x0 || r.y1 <= r.y0)
    throw std::invalid_argument("--region '" + text + "': needs x0 < x1 and y0 < y1");
  return r;
}

}  // namespace lb
