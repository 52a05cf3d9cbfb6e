#include "bake/metrics/error_image.h"

#include <algorithm>
#include <cmath>

namespace lb {

std::array<float, 3> false_colour(double error, double max_error) {
  if (error < 0.0) return {0.2f, 0.2f, 0.2f};  // not compared (linear 0.2 is mid grey in sRGB)
  // Control points of a dark-to-light ramp (linear display RGB), evenly spaced in t.
  static constexpr float kRamp[][3] = {{0.0f, 0.0f, 0.0f},   {0.05f, 0.02f, 0.45f},
                                       {0.55f, 0.03f, 0.45f}, {0.95f, 0.3f, 0.04f},
                                       {1.0f, 0.95f, 0.55f}};
  constexpr int kSegments = 4;
  const double t = std::clamp(error / max_error, 0.0, 1.0) * kSegments;
  const int i = std::min(int(t), kSegments - 1);
  const float f = float(t - i);
  std::array<float, 3> rgb{};
  for (int c = 0; c < 3; ++c) rgb[size_t(c)] = kRamp[i][c] + f * (kRamp[i + 1][c] - kRamp[i][c]);
  return rgb;
}

Image false_colour_image(const Image& error, double max_error) {
  Image picture(error.width, error.height, 3);
  for (int y = 0; y < error.height; ++y)
    for (int x = 0; x < error.width; ++x) {
      const auto rgb = false_colour(error.at(x, y), max_error);
      for (int c = 0; c < 3; ++c) picture.at(x, y, c) = rgb[size_t(c)];
    }
  return picture;
}

}  // namespace lb
