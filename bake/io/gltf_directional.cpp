#include "bake/io/gltf_directional.h"

#include <algorithm>
#include <cmath>

namespace lb {

std::vector<uint8_t> encode_l1_ratios(const std::vector<vec3>& l0, const std::vector<vec3>& l1,
                                      const std::vector<float>* share) {
  const size_t channels = share ? 4 : 3;
  std::vector<uint8_t> bytes(l1.size() * channels, 128);
  for (size_t i = 0; i < l1.size() && i < l0.size(); ++i) {
    for (size_t c = 0; c < 3; ++c) {
      if (!(l0[i][int(c)] > 0.0f)) continue;
      const float r = std::clamp(l1[i][int(c)] / l0[i][int(c)], -1.0f, 1.0f);
      bytes[i * channels + c] = uint8_t(128 + int(std::lround(127.0f * r)));
    }
    if (share)
      bytes[i * channels + 3] =
          uint8_t(std::lround(255.0f * std::clamp(i < share->size() ? (*share)[i] : 0.0f,
                                                  0.0f, 1.0f)));
  }
  return bytes;
}

vec3 decode_l1_ratio(const uint8_t* texel, vec3 l0) {
  vec3 out;
  for (int c = 0; c < 3; ++c) out[c] = (float(texel[c]) - 128.0f) / 127.0f * l0[c];
  return out;
}

}  // namespace lb
