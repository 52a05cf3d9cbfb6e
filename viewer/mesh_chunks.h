#pragma once
// Spatial chunks of a mesh's triangles for culling: the triangles reordered so that each
// chunk is one contiguous range of at most `max_triangles`, with its bounding box. A mesh
// small enough is one chunk in its own order (the bundled scenes draw exactly as before).

#include <cstdint>
#include <vector>

#include "bake/scene.h"

namespace lb {

// Triangles per chunk at most: big enough that a room's wall or a furniture part is one
// draw, small enough that a 10M-triangle level has a few thousand boxes to test per pass.
constexpr int kChunkTriangles = 4096;

struct MeshChunk {
  uint32_t first_triangle = 0;  // in MeshChunks::order
  uint32_t triangle_count = 0;
  Bounds bounds;
};

struct MeshChunks {
  std::vector<uint32_t> order;  // order[k]: the mesh triangle drawn k-th
  std::vector<MeshChunk> chunks;
};

// Splits at the median triangle centroid along the longest axis of the centroids' box until
// every part holds at most `max_triangles`; the triangles within a chunk keep the mesh's
// order. Deterministic (ties broken by triangle index).
MeshChunks make_mesh_chunks(const Mesh& mesh, int max_triangles = kChunkTriangles);

}  // namespace lb
