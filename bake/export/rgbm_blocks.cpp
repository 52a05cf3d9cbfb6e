#include "bake/export/rgbm_blocks.h"

#include <algorithm>
#include <cmath>
#include <iterator>

#include "bake/io/image_io.h"

namespace lb {

namespace {

constexpr int kBlock = 4;  // UASTC's block side

// What each of `to` texels takes from the `from` texels of a row or column: texel i covers
// [i, i + 1) x from / to of them, each weighted by its overlap, the weights summing to 1.
struct Footprint {
  int first = 0;
  std::vector<float> weights;
};
std::vector<Footprint> footprints(int from, int to) {
  std::vector<Footprint> out(static_cast<size_t>(to));
  const double ratio = double(from) / double(to);
  for (int i = 0; i < to; ++i) {
    const double begin = i * ratio, end = (i + 1) * ratio;
    Footprint& f = out[size_t(i)];
    f.first = int(std::floor(begin));
    for (int k = f.first; k < from && k < end; ++k)
      f.weights.push_back(
          float((std::min(end, double(k + 1)) - std::max(begin, double(k))) / ratio));
  }
  return out;
}

}  // namespace

std::vector<uint8_t> encode_rgbm_blocks(int width, int height, const std::vector<vec3>& radiance,
                                        float scale) {
  std::vector<uint8_t> rgba(size_t(width) * size_t(height) * 4);
  for (int by = 0; by < height; by += kBlock)
    for (int bx = 0; bx < width; bx += kBlock) {
      const int x_end = std::min(bx + kBlock, width), y_end = std::min(by + kBlock, height);
      float top = 0.0f;
      for (int y = by; y < y_end; ++y)
        for (int x = bx; x < x_end; ++x) {
          const vec3& r = radiance[size_t(y) * size_t(width) + size_t(x)];
          top = std::max({top, r.x / scale, r.y / scale, r.z / scale});
        }
      const int need = int(std::ceil(top * 255.0f));
      const uint8_t* fits = std::lower_bound(std::begin(kBlockMultipliers),
                                             std::end(kBlockMultipliers), need);
      const int m = fits == std::end(kBlockMultipliers) ? 255 : *fits;
      for (int y = by; y < y_end; ++y)
        for (int x = bx; x < x_end; ++x) {
          const size_t i = size_t(y) * size_t(width) + size_t(x);
          uint8_t* texel = &rgba[i * 4];
          for (int c = 0; c < 3; ++c)
            texel[c] = unit_to_byte(radiance[i][c] / scale * 255.0f / float(m));
          texel[3] = uint8_t(m);
        }
    }
  return rgba;
}

std::vector<vec3> box_downsample(int width, int height, const std::vector<vec3>& radiance) {
  const int to_width = std::max(1, width >> 1), to_height = std::max(1, height >> 1);
  const std::vector<Footprint> across = footprints(width, to_width);
  const std::vector<Footprint> down = footprints(height, to_height);
  std::vector<vec3> rows(size_t(to_width) * size_t(height), vec3(0.0f));  // columns first
  for (int y = 0; y < height; ++y)
    for (int i = 0; i < to_width; ++i) {
      const Footprint& f = across[size_t(i)];
      vec3 sum(0.0f);
      for (size_t k = 0; k < f.weights.size(); ++k)
        sum += f.weights[k] * radiance[size_t(y) * size_t(width) + size_t(f.first) + k];
      rows[size_t(y) * size_t(to_width) + size_t(i)] = sum;
    }
  std::vector<vec3> out(size_t(to_width) * size_t(to_height), vec3(0.0f));
  for (int j = 0; j < to_height; ++j) {
    const Footprint& f = down[size_t(j)];
    for (int i = 0; i < to_width; ++i) {
      vec3 sum(0.0f);
      for (size_t k = 0; k < f.weights.size(); ++k)
        sum += f.weights[k] * rows[(size_t(f.first) + k) * size_t(to_width) + size_t(i)];
      out[size_t(j) * size_t(to_width) + size_t(i)] = sum;
    }
  }
  return out;
}

std::vector<RgbmLevel> rgbm_block_levels(int width, int height,
                                         const std::vector<vec3>& radiance, float scale,
                                         bool mipmaps) {
  std::vector<RgbmLevel> levels;
  std::vector<vec3> level = radiance;
  for (;;) {
    levels.push_back({width, height, encode_rgbm_blocks(width, height, level, scale)});
    if (!mipmaps || (width == 1 && height == 1)) return levels;
    level = box_downsample(width, height, level);
    width = std::max(1, width >> 1);
    height = std::max(1, height >> 1);
  }
}

}  // namespace lb
