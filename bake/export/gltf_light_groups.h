#pragma once
// LIGHTBAKE_lightmap_groups (issue 39): a bake's light groups (bake/light_groups.h) as lightmap
// layers, one 8-bit map per group beside MOZ_lightmap, whose map holds their sum (every weight
// 1), so an engine without the extension draws the default mix (docs/export.md, "Light groups"):
//   material.extensions.LIGHTBAKE_lightmap_groups = { "layers": [
//     {"name": "day", "weight": 1, "index": T, "texCoord": 1, "intensity": pi * scale}, ...] }
// Each layer is encoded as the MOZ_lightmap texture is (extras.lightbake_lightmap.encoding),
// with its own scale. An engine draws the baked light as
//     sum over layers of  w * intensity * texel(uv1)        (in place of MOZ_lightmap's term)
// with w its own weights (`weight`: the default, 1), and scales each group's lights with them.

#include <vector>

#include "bake/bake_result.h"
#include "bake/lightmap/lightmap.h"
#include "bake/progress.h"

namespace lb {

inline constexpr char kLightGroupsExtension[] = "LIGHTBAKE_lightmap_groups";

// Each of bake.light_groups' lightmaps: the bake's light and the scene's lights of that group
// alone (bake_lightmap with `params`). Empty when the bake has no groups.
std::vector<Lightmap> bake_group_lightmaps(const Scene& scene, const BakeResult& bake,
                                           const LightmapParams& params,
                                           const Progress& progress = {});

}  // namespace lb
