#pragma once
// A mesh's own lightmap UVs (glTF TEXCOORD_1, Blender's second UV map), checked before the
// atlas keeps them (issue 36).
//
// Islands: the triangles joined by shared vertices or by vertices at the very same UV (an
// exporter splits vertices at hard edges without moving them in UV). Each island becomes a chart
// of its own, packed with the atlas's padding like an unwrapped chart, so two islands never
// share a texel however close the artist laid them out; within an island the layout is kept.
//
// Problems, each a count of triangles:
//   zero_area    no area in UV but some in space (a texel's light is smeared over surface of any
//                size; a sliver in space too, as the contact cuts make, is not counted);
//   flipped      wound against the rest of its island (the island folds over itself);
//   overlapping  overlapping another triangle of its island in UV (two surfaces in one texel,
//                also two islands stacked on each other: equal UVs join them into one).
// Folds and overlaps put two surfaces' light in one texel, so the atlas replaces such UVs with
// its own unless told to keep them (AtlasParams::generate_given_uvs); zero-area triangles alone
// are kept, with the warning.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "bake/scene.h"

namespace lb {

struct GivenUvCheck {
  size_t triangles = 0;
  size_t zero_area = 0;
  size_t flipped = 0;
  size_t overlapping = 0;
  // Per triangle, its island (0 .. islands - 1), -1 for zero-area triangles of no island.
  std::vector<int> island;
  int islands = 0;

  bool folds() const { return flipped + overlapping > 0; }
  // "3 overlapping, 2 flipped and 1 zero-area of 120 triangles" (only the nonzero counts).
  std::string describe() const;
};

// Checks mesh.lightmap_uvs (as long as its positions). Cost: the triangles, plus each pair of
// triangles of one island whose UV boxes meet in a grid of about one cell per triangle.
GivenUvCheck check_given_uvs(const Mesh& mesh);

}  // namespace lb
