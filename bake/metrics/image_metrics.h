#pragma once
// Error metrics of a rendered image A against a reference B (usually a converged path-traced
// image), for the speed-against-accuracy charts and `lightbake compare`.
//
// Definitions (sums over the compared pixels P and the colour channels c, N = |P| * channels):
//   eps            = epsilon_fraction * mean(B) over P and c           (unless epsilon > 0 given)
//   mean relative  MRE    = 1/N sum |a - b| / (|b| + eps)
//   relative MSE   relMSE = 1/N sum (a - b)^2 / (b^2 + eps^2)
//   RMSE                  = sqrt(1/N sum (a - b)^2)                     (units of the images)
//   sum ratio      per channel sum_P a / sum_P b, and total over all channels (absolute energy:
//                  1.0 means the same total light, 0.96 means A is 4% too dark)
// eps keeps dark pixels from dominating the relative errors; it is relative to the reference's
// mean so that the same setting works for scenes whose radiance differs by orders of magnitude
// (W/(sr m^2) in our scenes range from ~0.1 to ~100). |b| rather than b: a reference minus a
// term (B - C, for per-term comparisons) can be slightly negative where it is noisy.
// Compared pixels: inside the region (half-open [x0, x1) x [y0, y1), pixels, origin at the top
// left) and, with a mask, where the mask's first channel is > 0.5. Colour channels: the first
// min(channels, 3); a 4th (alpha) channel is ignored.
// No GL, no files: see app/cmd_compare.cpp for the command line.

#include <array>
#include <string>

#include "bake/io/image_io.h"

namespace lb {

struct PixelRegion {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // half-open; x1 <= x0 or y1 <= y0 means the whole image
  bool whole() const { return x1 <= x0 || y1 <= y0; }
};

struct CompareParams {
  PixelRegion region;          // default: the whole image
  const Image* mask = nullptr;  // same size as the images; first channel > 0.5 is compared
  // eps = epsilon_fraction * mean(B); 0.01 = 1% of the reference's mean radiance, typical range
  // 1e-3 .. 0.1 (smaller weights dark pixels more).
  double epsilon_fraction = 0.01;
  double epsilon = 0.0;  // > 0: an absolute eps in the images' units, overrides the fraction
};

struct ImageMetrics {
  double mean_relative_error = 0.0;  // MRE, 1
  double relative_mse = 0.0;         // relMSE, 1
  double rmse = 0.0;                 // image units (W/(sr m^2) for radiance)
  std::array<double, 3> sum_ratio{};  // per colour channel, sum A / sum B (unused channels: 0)
  double sum_ratio_total = 0.0;       // over all colour channels
  double epsilon = 0.0;               // the eps used, image units
  double mean_reference = 0.0;        // mean(B) over the compared pixels and channels
  size_t pixels = 0;                  // compared pixels
  int channels = 0;                   // colour channels compared
  size_t differing_values = 0;        // compared values whose bits differ (0: identical)
};

// Throws std::invalid_argument when the sizes or colour channel counts differ, the mask's size
// differs, the region lies outside the image, or no pixel is left to compare. The messages name
// the image ("A", "B", "mask") so the caller can put the file name in front.
ImageMetrics compare_to_reference(const Image& image, const Image& reference,
                                  const CompareParams& params = {});

// One JSON object on one line: {"mre":..,"relmse":..,"rmse":..,"sum_ratio":[r,g,b],
// "sum_ratio_total":..,"epsilon":..,"mean_reference":..,"pixels":..,"channels":..,
// "differing_values":..}.
std::string metrics_json(const ImageMetrics& metrics);

// Per-pixel relative error |a - b| / (|b| + eps), averaged over the colour channels; one
// channel. Pixels not compared (outside the region or the mask) are -1.
Image relative_error_image(const Image& image, const Image& reference, const CompareParams& params,
                           double epsilon);

// B - C per value, for comparing one term against the reference minus the others. Same checks
// as compare_to_reference.
Image subtract_images(const Image& minuend, const Image& subtrahend);

// "x0,y0,x1,y1" in pixels; throws std::invalid_argument quoting the text.
PixelRegion parse_region(const std::string& text);

}  // namespace lb
