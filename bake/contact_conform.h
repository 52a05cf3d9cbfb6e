#pragma once
// Scene meshes conformed to where other geometry meets them (issue 36), done once by the
// loaders so that every pass, the viewer and the export see the same triangles.
//
// A lightmap texel is read with bilinear filtering across its neighbours, so a chart that runs
// under a wall or a block mixes the light of both sides: a floor under a 1 mm partition took
// 0.6% of the lit room's light on the dark side at 10 texels/m, however its texels were filled,
// because the texels either side of the wall are neighbours. So each diffuse mesh is cut along
// the planes of other meshes' triangles that meet it (contact_cuts.h, step 1: exact along the
// contact line, a T-junction where it ends), its triangles inside other geometry are marked
// `Mesh::hidden` (step 2's coverage probes), and the atlas never grows a chart across from a
// hidden triangle to an open one: the floor either side of a wall, and the footprint of a
// block, become charts of their own, with a gutter between them.
//
// The same surface, a few more triangles (the Cornell box 36 -> 128, the generated 2 x 2 level
// 3152 -> 4259). Small cutters are skipped
// as radiosity skips them: a mesh whose part in a receiving plane fits in a square of
// `kContactMinFootprintTexels` automatic texels (scene diagonal / 256 each) does not cut.

#include <cstddef>

#include "bake/scene.h"

namespace lb {

inline constexpr float kContactMinFootprintTexels = 2.0f;

struct ConformStats {
  size_t meshes_cut = 0;       // meshes that gained triangles
  size_t triangles_added = 0;  // over the scene
  size_t hidden = 0;           // triangles marked hidden
};

// Cuts every diffuse mesh along its contacts with the other meshes and marks the hidden
// triangles of every diffuse mesh (an Embree scene of the cut meshes, 5 probes a triangle).
// Idempotent: a conformed scene gains no triangle, its hidden flags are the same.
ConformStats conform_to_contacts(Scene& scene);

}  // namespace lb
