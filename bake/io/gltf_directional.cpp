#include "bake/io/gltf_directional.h"

#include <algorithm>
#include <cmath>

namespace lb {

std::vector<uint8_t> encode_l1_ratios(const std::vector<vec3>& l0, const std::vector<vec3>& l1) {
  std::vector<uint8_t> bytes(l1.size() * 3, 128);
  for (size_t i = 0; i < l1.size() && i < l0.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      if (!(l0[i][c] > 0.0f)) continue;
      const float r = std::clamp(l1[i][c] / l0[i][c], -1.0f, 1.0f);
      bytes[i * 3 + size_t(c)] = uint8_t(128 + int(std::lround(127.0f * r)));
    }
  return bytes;
}

vec3 decode_l1_ratio(const uint8_t* texel, vec3 l0) {
  vec3 out;
  for (int c = 0; c < 3; ++c) out[c] = (float(texel[c]) - 128.0f) / 127.0f * l0[c];
  return out;
}

}  // namespace lb
