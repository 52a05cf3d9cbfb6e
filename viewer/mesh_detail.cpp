#include "viewer/mesh_detail.h"

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModHausdorffT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <unordered_map>

#include "viewer/box_clusters.h"

namespace lb {

namespace {

using ChunkMesh = OpenMesh::TriMesh_ArrayKernelT<>;
using Decimater = OpenMesh::Decimater::DecimaterT<ChunkMesh>;
using Quadric = OpenMesh::Decimater::ModQuadricT<ChunkMesh>::Handle;
using Hausdorff = OpenMesh::Decimater::ModHausdorffT<ChunkMesh>::Handle;
using NormalFlipping = OpenMesh::Decimater::ModNormalFlippingT<ChunkMesh>::Handle;

// Each level's error bound as a fraction of the chunk's diagonal: a level is drawn once the
// chunk spans fewer than about 1 / fraction pixels (at one pixel of error allowed).
constexpr float kLevelErrors[] = {1.0f / 512, 1.0f / 128, 1.0f / 32, 1.0f / 8};
// A level is kept only if it drops at least this share of the triangles of the one before.
constexpr float kMinReduction = 0.25f;
// A collapse may turn a triangle's normal by at most this much (degrees): keeps thin parts
// from folding over themselves.
constexpr float kMaxNormalTurn = 60.0f;

// The levels of one chunk: its triangles `tris` (mesh triangle indices), appended to `out`.
void simplify_chunk(const Mesh& mesh, const uint32_t* tris, uint32_t count, const Bounds& bounds,
                    std::vector<int>& local_of, MeshDetail& out,
                    std::vector<DetailLevel>& levels) {
  ChunkMesh chunk;
  std::vector<uint32_t> mesh_vertex;  // local vertex -> mesh vertex
  std::vector<uint32_t> face_source;  // local face -> mesh triangle
  std::vector<uint32_t> kept_as_is;   // triangles OpenMesh cannot take (non-manifold, degenerate)
  auto local = [&](uint32_t v) {
    if (local_of[v] < 0) {
      local_of[v] = int(mesh_vertex.size());
      mesh_vertex.push_back(v);
      const vec3 p = mesh.positions[v];
      chunk.add_vertex(ChunkMesh::Point(p.x, p.y, p.z));
    }
    return ChunkMesh::VertexHandle(local_of[v]);
  };
  for (uint32_t k = 0; k < count; ++k) {
    const uvec3 tri = mesh.triangles[tris[k]];
    const ChunkMesh::VertexHandle a = local(tri.x), b = local(tri.y), c = local(tri.z);
    const bool added = a != b && b != c && a != c && chunk.add_face(a, b, c).is_valid();
    if (added)
      face_source.push_back(tris[k]);
    else
      kept_as_is.push_back(tris[k]);
  }
  // The vertices of the triangles kept as they are stay put, so those triangles stay joined.
  std::vector<int> pinned;
  for (uint32_t t : kept_as_is) {
    for (int k = 0; k < 3; ++k) pinned.push_back(local_of[mesh.triangles[t][k]]);
  }
  for (uint32_t v : mesh_vertex) local_of[v] = -1;  // ready for the next chunk
  if (face_source.size() < kMinDetailTriangles) return;

  chunk.request_vertex_status();
  chunk.request_edge_status();
  chunk.request_face_status();
  chunk.request_face_normals();
  chunk.update_face_normals();
  for (const ChunkMesh::VertexHandle v : chunk.vertices()) {
    if (chunk.is_boundary(v)) chunk.status(v).set_locked(true);
  }
  for (int v : pinned) chunk.status(ChunkMesh::VertexHandle(v)).set_locked(true);

  // Quadrics order the collapses (the cheapest first); the Hausdorff module allows one only
  // while every vertex removed so far stays within the level's error of the triangles left.
  Decimater decimater(chunk);
  Quadric quadric;
  Hausdorff hausdorff;
  NormalFlipping flipping;
  decimater.add(quadric);
  decimater.add(hausdorff);
  decimater.add(flipping);
  decimater.module(quadric).unset_max_err();
  decimater.module(flipping).set_max_normal_deviation(kMaxNormalTurn);
  if (!decimater.initialize()) return;

  const float diagonal = bounds.diagonal();
  size_t previous = count;
  for (float fraction : kLevelErrors) {
    const double error = double(diagonal * fraction);
    decimater.module(hausdorff).set_tolerance(ChunkMesh::Scalar(error));
    decimater.decimate(0);  // every legal collapse under the bound
    DetailLevel level;
    level.first_triangle = uint32_t(out.triangles.size());
    level.error = float(error);
    for (const ChunkMesh::FaceHandle f : chunk.faces()) {
      if (chunk.status(f).deleted()) continue;
      uvec3 tri;
      int k = 0;
      for (const ChunkMesh::VertexHandle v : chunk.fv_range(f))
        tri[k++] = mesh_vertex[size_t(v.idx())];
      out.triangles.push_back(tri);
      out.source.push_back(face_source[size_t(f.idx())]);
    }
    for (uint32_t t : kept_as_is) {
      out.triangles.push_back(mesh.triangles[t]);
      out.source.push_back(t);
    }
    level.triangle_count = uint32_t(out.triangles.size() - level.first_triangle);
    if (float(level.triangle_count) > (1.0f - kMinReduction) * float(previous)) {
      // Too little gained: drop it (a coarser bound may still gain enough).
      out.triangles.resize(level.first_triangle);
      out.source.resize(level.first_triangle);
      continue;
    }
    previous = level.triangle_count;
    levels.push_back(level);
  }
}

// The triangles' corners and chunks alone: instances share them.
uint64_t topology_hash(const Mesh& mesh, const MeshChunks& chunks) {
  uint64_t hash = 1469598103934665603ull;  // FNV-1a over the words
  auto mix = [&](uint64_t word) {
    hash ^= word;
    hash *= 1099511628211ull;
  };
  mix(mesh.positions.size());
  mix(mesh.triangles.size());
  for (const uvec3& t : mesh.triangles) mix((uint64_t(t.x) << 42) ^ (uint64_t(t.y) << 21) ^ t.z);
  for (uint32_t t : chunks.order) mix(t);
  return hash;
}

float edge_length(const Mesh& mesh, const uvec3& t, int k) {
  return glm::length(mesh.positions[t[(k + 1) % 3]] - mesh.positions[t[k]]);
}

// The same triangles and chunks, every edge as long to rounding: a rigid motion (or a mirror
// image) of `a`.
bool congruent(const Mesh& a, const MeshChunks& a_chunks, const Mesh& b,
               const MeshChunks& b_chunks) {
  if (a.positions.size() != b.positions.size() || a.triangles != b.triangles ||
      a_chunks.order != b_chunks.order || a_chunks.chunks.size() != b_chunks.chunks.size())
    return false;
  Bounds box;
  float reach = 0.0f;
  for (const vec3& p : b.positions) {
    box.extend(p);
    reach = std::max(reach, glm::length(p));
  }
  // Float positions placed by a transform round to about 1e-7 of their magnitude.
  const float tolerance = 1e-5f * box.diagonal() + 1e-6f * reach;
  for (const uvec3& t : a.triangles) {
    for (int k = 0; k < 3; ++k) {
      if (std::abs(edge_length(a, t, k) - edge_length(b, t, k)) > tolerance) return false;
    }
  }
  return true;
}

}  // namespace

MeshDetail make_mesh_detail(const Mesh& mesh, const MeshChunks& chunks) {
  MeshDetail out;
  out.chunk_levels.resize(chunks.chunks.size());
  std::vector<int> local_of(mesh.positions.size(), -1);
  for (size_t c = 0; c < chunks.chunks.size(); ++c) {
    const MeshChunk& chunk = chunks.chunks[c];
    if (chunk.triangle_count < kMinDetailTriangles) continue;
    simplify_chunk(mesh, chunks.order.data() + chunk.first_triangle, chunk.triangle_count,
                   chunk.bounds, local_of, out, out.chunk_levels[c]);
  }
  return out;
}

std::vector<MeshDetail> make_scene_detail(const std::vector<Mesh>& meshes,
                                          const std::vector<MeshChunks>& chunks) {
  // Each mesh's representative: the first congruent mesh before it (by topology hash first).
  std::vector<size_t> representative(meshes.size());
  std::unordered_map<uint64_t, std::vector<size_t>> by_hash;
  for (size_t m = 0; m < meshes.size(); ++m) {
    representative[m] = m;
    if (meshes[m].triangles.size() < kMinDetailTriangles) continue;
    std::vector<size_t>& candidates = by_hash[topology_hash(meshes[m], chunks[m])];
    for (size_t r : candidates) {
      if (congruent(meshes[r], chunks[r], meshes[m], chunks[m])) {
        representative[m] = r;
        break;
      }
    }
    if (representative[m] == m) candidates.push_back(m);
  }
  std::vector<MeshDetail> detail(meshes.size());
  tbb::parallel_for(size_t(0), meshes.size(), [&](size_t m) {
    if (representative[m] == m) detail[m] = make_mesh_detail(meshes[m], chunks[m]);
  });
  for (size_t m = 0; m < meshes.size(); ++m) {
    if (representative[m] != m) detail[m] = detail[representative[m]];
  }
  return detail;
}

DetailView make_detail_view(const glm::mat4& world_to_clip, vec3 eye, int image_height,
                            float max_pixels) {
  // Clip y is row 1 of the matrix: 1 / tan(fov / 2) times the view's unit up axis (plus a
  // jitter's sliver of its forward axis), so the length of its first three terms is the
  // projection's vertical scale.
  const glm::vec3 row(world_to_clip[0][1], world_to_clip[1][1], world_to_clip[2][1]);
  DetailView view;
  view.eye = eye;
  view.pixels_per_radian = 0.5f * float(image_height) * glm::length(row);
  view.max_pixels = max_pixels;
  return view;
}

int pick_detail_level(const std::vector<DetailLevel>& levels, const Bounds& bounds,
                      const DetailView& view) {
  if (levels.empty() || !view.active()) return -1;
  const float distance = box_distance(bounds, view.eye);
  const float allowed = view.max_pixels * distance / view.pixels_per_radian;
  int pick = -1;
  for (size_t k = 0; k < levels.size() && levels[k].error <= allowed; ++k) pick = int(k);
  return pick;
}

}  // namespace lb
