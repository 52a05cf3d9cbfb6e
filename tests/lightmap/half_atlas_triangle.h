#pragma once
// One triangle over the lower-left half of a 64 x 100 atlas, world = (u, v, 0): the rows'
// surface falls from a whole row at the bottom to nothing at the top.

#include "bake/scene.h"

namespace lb::half_atlas {

inline constexpr int kWidth = 64, kHeight = 100;

inline Mesh triangle() {
  Mesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.lightmap_uvs = {{0, 0}, {1, 0}, {0, 1}};
  mesh.triangles = {{0, 1, 2}};
  return mesh;
}

}  // namespace lb::half_atlas
