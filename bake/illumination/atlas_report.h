#pragma once
// What the lightmap of a scene will be, before any bake (`lightbake info --lightmap`, issue 36):
// the atlas a bake builds at a texel density, with each mesh's density, charts, texels and the
// state of its own lightmap UVs, and the map's size in the files and in an engine's memory.
// The meshes that catch caustics may get finer texels in a real bake (the caustic pilot,
// illumination.h); this is the atlas before the pilot.

#include <cstddef>
#include <string>
#include <vector>

#include "bake/illumination/atlas.h"

namespace lb {

struct MeshLightmapRow {
  size_t mesh = 0;
  float texels_per_m = 0.0f;
  size_t charts = 0;
  size_t texels = 0;         // nodes holding its surface
  std::string uvs;           // "generated", "own (N islands)", "own UVs replaced: ..." 
};

struct LightmapReport {
  int width = 0, height = 0;
  float texels_per_m = 0.0f;  // the atlas's default density
  size_t valid_texels = 0;
  std::vector<MeshLightmapRow> meshes;  // every mesh with a map, in scene order
  std::vector<std::string> warnings;    // the atlas's
  // Bytes: the 8-bit RGBA texture an engine uploads, with its mip chain (4/3), and the EXR's
  // half-float RGB before compression.
  size_t gpu_bytes() const { return size_t(width) * size_t(height) * 4 * 4 / 3; }
  size_t half_bytes() const { return size_t(width) * size_t(height) * 6; }
};

// texel_size: metres per texel, 0 = the automatic rule (atlas.h).
LightmapReport lightmap_report(const Scene& scene, float texel_size, int padding = 3);

}  // namespace lb
