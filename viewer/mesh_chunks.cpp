#include "viewer/mesh_chunks.h"

#include <algorithm>

namespace lb {

namespace {

Bounds triangle_bounds(const Mesh& mesh, const uint32_t* begin, const uint32_t* end) {
  Bounds bounds;
  for (const uint32_t* t = begin; t != end; ++t) {
    for (int k = 0; k < 3; ++k) bounds.extend(mesh.positions[mesh.triangles[*t][k]]);
  }
  return bounds;
}

void split(const Mesh& mesh, const std::vector<vec3>& centroids, uint32_t* begin, uint32_t* end,
           size_t max_triangles, MeshChunks& out) {
  const size_t count = size_t(end - begin);
  if (count <= max_triangles) {
    std::sort(begin, end);  // the mesh's own order within the chunk
    MeshChunk chunk;
    chunk.first_triangle = uint32_t(begin - out.order.data());
    chunk.triangle_count = uint32_t(count);
    chunk.bounds = triangle_bounds(mesh, begin, end);
    out.chunks.push_back(chunk);
    return;
  }
  Bounds spread;
  for (const uint32_t* t = begin; t != end; ++t) spread.extend(centroids[*t]);
  const vec3 extent = spread.extent();
  const int axis =
      extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
  uint32_t* middle = begin + count / 2;
  std::nth_element(begin, middle, end, [&](uint32_t a, uint32_t b) {
    const float ca = centroids[a][axis], cb = centroids[b][axis];
    return ca < cb || (ca == cb && a < b);
  });
  split(mesh, centroids, begin, middle, max_triangles, out);
  split(mesh, centroids, middle, end, max_triangles, out);
}

}  // namespace

MeshChunks make_mesh_chunks(const Mesh& mesh, int max_triangles) {
  MeshChunks out;
  const size_t count = mesh.triangles.size();
  out.order.resize(count);
  for (size_t t = 0; t < count; ++t) out.order[t] = uint32_t(t);
  if (count == 0) return out;
  std::vector<vec3> centroids;
  if (count > size_t(std::max(1, max_triangles))) {
    centroids.resize(count);
    for (size_t t = 0; t < count; ++t) {
      const uvec3 tri = mesh.triangles[t];
      centroids[t] = (mesh.positions[tri.x] + mesh.positions[tri.y] + mesh.positions[tri.z]) / 3.0f;
    }
  }
  split(mesh, centroids, out.order.data(), out.order.data() + count,
        size_t(std::max(1, max_triangles)), out);
  return out;
}

}  // namespace lb
