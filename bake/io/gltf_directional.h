#pragma once
// LIGHTBAKE_lightmap_directional (issue 38): the L1 band of an exported lightmap
// (bake/sh_projection.h) as three 8-bit PNGs, one per world axis, beside the MOZ_lightmap
// texture (docs/export.md, "Directional maps"):
//   material.extensions.LIGHTBAKE_lightmap_directional = {
//     "l1": [{"index": X, "texCoord": 1}, {"index": Y, ...}, {"index": Z, ...}],
//     "encoding": "ratio8", "space": "world", "share": false }
// Each byte holds the channel's L1 over its L0 (in [-1, 1] once de-ringed):
//   byte = 128 + round(127 r),  r = L1_c / L0_c;   decode  L1_c = (byte - 128) / 127 * L0_c
// (0 at L0_c = 0), so 0 is exact and the decode needs L0 only, which every reader already has.
// "share": false (the default, `export --directional`): three RGB maps, 4x the plain map's
// bytes, s = 0. "share": true (`--directional-share`): the x map is RGBA, its alpha s, the
// direct term's share of L0: alpha = round(255 s). A file without the key (before it) has s
// in the x map's alpha when that map has one. Drawn as (n the world shading normal, n0 the
// unbumped one, W = (1 + s) / 2)
//   E(n)/pi = max(0, L0 (1 - W (1 - n . n0)) + L1_x n_x + L1_y n_y + L1_z n_z).
#include <cstdint>
#include <vector>

#include "bake/scene.h"

namespace lb {

inline constexpr char kDirectionalExtension[] = "LIGHTBAKE_lightmap_directional";

// RGB bytes of one axis's ratio map (texels of `l0` and `l1` in the same order); RGBA with
// `share` (s, the x map's) in alpha.
std::vector<uint8_t> encode_l1_ratios(const std::vector<vec3>& l0, const std::vector<vec3>& l1,
                                      const std::vector<float>* share = nullptr);
// L1 of one texel from its three bytes and its L0.
vec3 decode_l1_ratio(const uint8_t* texel, vec3 l0);

}  // namespace lb
