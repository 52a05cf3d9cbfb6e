#pragma once
// Re-import: the baked light of a glTF written by `lightbake export` (gltf_export.h), so that
// `snapshot out.glb`, `render out.glb` and `view out.glb` show it without baking again. The
// scene itself comes from the ordinary glTF loader (load_scene); this reads the MOZ_lightmap
// map (the complete baked light of every diffuse mesh), preferring the half-float EXR beside
// the file (named in the material's extras), then the Radiance HDR, to the 8-bit PNG inside
// it. A map exported with `--contents all` holds the direct light too:
// IlluminationMaps::holds_direct_light is then set and renderers add no direct light of their
// own. COLOR_0, which exports before issue 12 carried (vertex radiosity), is still read. Light
// groups' layers (LIGHTBAKE_lightmap_groups) become the bake's groups, weighed by
// blend_light_groups (`--group-weights` on an export).

#include <string>

#include "bake/bake_result.h"

namespace lb {

// `scene` must be load_scene(path). Every exported mesh with COLOR_0 becomes a radiosity mesh
// (the scene mesh itself: the export wrote the refined mesh) with radiance COLOR_0 x
// lightbake_color_0_scale, and one patch per triangle (the patches are not in the file); meshes
// whose material has MOZ_lightmap get the map through their TEXCOORD_1. Throws
// std::runtime_error naming `path` when the file is not a lightbake export or does not match
// `scene`.
BakeResult read_gltf_bake(const std::string& path, const Scene& scene);

}  // namespace lb
