#include "bake/contact_conform.h"

#include <tbb/parallel_for.h>

#include <algorithm>

#include <glm/glm.hpp>

#include "bake/accel.h"
#include "bake/contact_cuts.h"

namespace lb {

namespace {

// The cuts' rounding leaves a few slivers of no area (a cut vertex on an existing one, three
// cut points in a line) whose geometric normal is noise, possibly reversed. They cover nothing,
// so they are dropped by the loaders' own rule (zero_area_triangle), as are pieces facing
// against their shading normals: a conformed mesh passes the checks a loaded one does.
void drop_slivers(Mesh& mesh) {
  const bool has_normals = mesh.normals.size() == mesh.positions.size();
  std::erase_if(mesh.triangles, [&](const uvec3& t) {
    const vec3 a = mesh.positions[t.x], b = mesh.positions[t.y], c = mesh.positions[t.z];
    if (zero_area_triangle(a, b, c)) return true;
    if (!has_normals) return false;
    const vec3 n = glm::cross(b - a, c - a);
    const vec3 shading = mesh.normals[t.x] + mesh.normals[t.y] + mesh.normals[t.z];
    return !(glm::dot(n, shading) > 0.0f);
  });
}

}  // namespace

ConformStats conform_to_contacts(Scene& scene) {
  ConformStats stats;
  const size_t count = scene.meshes.size();
  if (count < 2) return stats;
  const Bounds bounds = scene_bounds(scene);
  if (bounds.empty()) return stats;
  const float min_footprint =
      kContactMinFootprintTexels * glm::length(bounds.extent()) / 256.0f;
  const float tolerance = contact_tolerance(scene);
  const BoxGrid grid = mesh_box_grid(scene);
  auto receives = [&](size_t m) {
    const Mesh& mesh = scene.meshes[m];
    return !mesh.triangles.empty() && mesh.material >= 0 &&
           size_t(mesh.material) < scene.materials.size() &&
           scene.materials[size_t(mesh.material)].is_diffuse();
  };
  // Every mesh is cut against the scene as loaded (the cutters' triangles, not their pieces):
  // the result does not depend on the order of the meshes.
  std::vector<Mesh> cut(count);
  std::vector<uint8_t> changed(count, 0);
  tbb::parallel_for(size_t(0), count, [&](size_t m) {
    if (!receives(m)) return;
    Mesh pieces = cut_along_contacts(scene.meshes[m], scene, grid, m, tolerance, min_footprint);
    if (pieces.triangles.size() == scene.meshes[m].triangles.size()) return;
    drop_slivers(pieces);
    changed[m] = 1;
    cut[m] = std::move(pieces);
  });
  for (size_t m = 0; m < count; ++m) {
    if (!changed[m]) continue;
    ++stats.meshes_cut;
    stats.triangles_added += cut[m].triangles.size() - std::min(cut[m].triangles.size(),
                                                                scene.meshes[m].triangles.size());
    scene.meshes[m] = std::move(cut[m]);
  }
  // Every receiver's coverage, cut or not: a scene conformed before (an export loaded back)
  // gains no cut but still needs its hidden triangles.
  const Accel accel(scene);
  const std::vector<uint8_t> closed = closed_meshes(scene);
  tbb::parallel_for(size_t(0), count, [&](size_t m) {
    if (!receives(m)) return;
    scene.meshes[m].hidden = covered_triangles(scene.meshes[m], accel, closed);
    for (uint8_t& h : scene.meshes[m].hidden) h = h == kCovered;  // sheltered surface is seen
  });
  for (size_t m = 0; m < count; ++m)
    for (uint8_t h : scene.meshes[m].hidden) stats.hidden += h;
  return stats;
}

}  // namespace lb
