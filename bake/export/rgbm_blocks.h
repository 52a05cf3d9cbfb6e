#pragma once
// RGBM for block compression (export --ktx2 --lightmap-encoding rgbm, docs/export.md "KTX2"):
// one multiplier m per 4x4 block instead of per texel, so UASTC's alpha is constant over each
// block it compresses, and m taken from the alphas UASTC keeps (kBlockMultipliers), so only
// the colour carries the compressor's error. With m per texel UASTC rounds m itself, and a
// code of a small m (a bright caustic sets the scale) is 10-30% of the texel's value. The
// decode is the PNG's RGBM: radiance = rgb / 255 * alpha / 255 * scale. Before compression a
// texel is within half a colour step of its block's m: |decoded - radiance| <= 0.5 / 255 *
// m / 255 * scale. Within a block filtering is exact (alpha is constant). RGBM cannot be
// box-filtered in its bytes, so the mip chain is built here in linear light and each level
// encoded on its own.

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

namespace lb {

using glm::vec3;

struct RgbmLevel {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> rgba;  // width * height * 4, top row first
};

// The alphas a block's m takes (m = alpha / 255), ascending: those basisu 1.15's UASTC keeps
// in a block of constant alpha, measured on 128 blocks of fig3_ring's map per alpha
// (bench/uastc_alpha_survival.py): transcoded to ASTC or ETC2 at most 1% of blocks change it,
// to BC7 at most 30%, by one code. (Most are values of ASTC's 48-level endpoint quantisation.)
// Neighbours are at most 2x apart (a block's brightest texel keeps 7 bits or more); the
// smallest, 16, bounds what BC7's one code costs a dim block (the measured choice:
// docs/export.md, "KTX2").
inline constexpr uint8_t kBlockMultipliers[] = {16,  32,  38,  48,  54,  70,  76,  86,
                                                92,  108, 124, 131, 147, 163, 179, 185,
                                                201, 207, 217, 223, 239, 247, 255};

// The texels' 4x4 blocks, each with the smallest m of kBlockMultipliers at or above
// 255 * block max / scale (so no colour byte clips).
std::vector<uint8_t> encode_rgbm_blocks(int width, int height, const std::vector<vec3>& radiance,
                                        float scale);

// Level k of a mip chain in linear light: max(1, width >> 1) x max(1, height >> 1) texels, each
// the area-weighted mean of the texels of `radiance` it covers (the mean is kept exactly).
std::vector<vec3> box_downsample(int width, int height, const std::vector<vec3>& radiance);

// Level 0 and, with `mipmaps`, every level down to 1 x 1 (KTX2's sizes), each RGBM-encoded in
// blocks at the map's one `scale` (a mean never exceeds the largest value: nothing clips).
std::vector<RgbmLevel> rgbm_block_levels(int width, int height,
                                         const std::vector<vec3>& radiance, float scale,
                                         bool mipmaps);

}  // namespace lb
