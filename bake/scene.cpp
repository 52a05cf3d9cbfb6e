#include "bake/scene.h"

#include <algorithm>
#include <cmath>

namespace lb {

const char* to_string(LampKind kind) {
  switch (kind) {
    case LampKind::point:
      return "point";
    case LampKind::spot:
      return "spot";
    case LampKind::directional:
      return "directional";
  }
  return "?";
}

const char* to_string(MaterialKind kind) {
  switch (kind) {
    case MaterialKind::diffuse:
      return "diffuse";
    case MaterialKind::mirror:
      return "mirror";
    case MaterialKind::glass:
      return "glass";
    case MaterialKind::glossy:
      return "glossy";
  }
  return "?";
}

Bounds scene_bounds(const Scene& scene) {
  Bounds bounds;
  for (const Mesh& mesh : scene.meshes)
    for (vec3 p : mesh.positions) bounds.extend(p);
  return bounds;
}

bool recentre_far_scene(Scene& scene) {
  const Bounds bounds = scene_bounds(scene);
  if (bounds.empty()) return false;
  const vec3 far = glm::max(glm::abs(bounds.min), glm::abs(bounds.max));
  const float farthest = std::max({far.x, far.y, far.z});
  // Within 64 m of the origin the offsets stay under a millimetre: leave such scenes as written.
  if (farthest <= std::max(2.0f * bounds.diagonal(), 64.0f)) return false;
  // Whole metres: p - shift is then exact for the points of a scene this far out (Sterbenz).
  const vec3 shift = glm::round(0.5f * (bounds.min + bounds.max));
  for (Mesh& mesh : scene.meshes)
    for (vec3& p : mesh.positions) p -= shift;
  for (Mesh& mesh : scene.dynamic_meshes)
    for (vec3& p : mesh.positions) p -= shift;
  for (Camera& camera : scene.cameras) {
    camera.position -= shift;
    camera.target -= shift;
  }
  for (Lamp& lamp : scene.lights) lamp.position -= shift;
  scene.probe_grid.origin -= shift;
  scene.world_origin += glm::dvec3(shift);
  return true;
}

void separate_dynamic_meshes(Scene& scene) {
  std::vector<Mesh> kept;
  for (Mesh& mesh : scene.meshes)
    (mesh.dynamic ? scene.dynamic_meshes : kept).push_back(std::move(mesh));
  scene.meshes = std::move(kept);
}

size_t triangle_count(const Scene& scene) {
  size_t count = 0;
  for (const Mesh& mesh : scene.meshes) count += mesh.triangles.size();
  return count;
}

static vec3 triangle_cross(const Mesh& mesh, size_t triangle) {
  const uvec3 t = mesh.triangles[triangle];
  const vec3 a = mesh.positions[t.x];
  return glm::cross(mesh.positions[t.y] - a, mesh.positions[t.z] - a);
}

float triangle_area(const Mesh& mesh, size_t triangle) {
  return 0.5f * glm::length(triangle_cross(mesh, triangle));
}

vec3 triangle_normal(const Mesh& mesh, size_t triangle) {
  const vec3 c = triangle_cross(mesh, triangle);
  const float length = glm::length(c);
  return length > 0.0f ? c / length : vec3(0.0f);
}

std::optional<UvDerivatives> uv_derivatives(const Mesh& mesh, size_t triangle) {
  if (mesh.uvs.empty()) return std::nullopt;
  const uvec3 tri = mesh.triangles[triangle];
  const vec3 e1 = mesh.positions[tri.y] - mesh.positions[tri.x];
  const vec3 e2 = mesh.positions[tri.z] - mesh.positions[tri.x];
  const vec2 d1 = mesh.uvs[tri.y] - mesh.uvs[tri.x];
  const vec2 d2 = mesh.uvs[tri.z] - mesh.uvs[tri.x];
  const float det = d1.x * d2.y - d1.y * d2.x;
  if (std::abs(det) < 1e-20f) return std::nullopt;
  return UvDerivatives{(e1 * d2.y - e2 * d1.y) / det, (e2 * d1.x - e1 * d2.x) / det};
}

float mesh_area(const Mesh& mesh) {
  double area = 0.0;
  for (size_t i = 0; i < mesh.triangles.size(); ++i) area += triangle_area(mesh, i);
  return float(area);
}

uint32_t append_vertex_copy(Mesh& mesh, uint32_t from) {
  mesh.positions.push_back(mesh.positions[from]);
  if (!mesh.normals.empty()) mesh.normals.push_back(mesh.normals[from]);
  if (!mesh.uvs.empty()) mesh.uvs.push_back(mesh.uvs[from]);
  if (!mesh.lightmap_uvs.empty()) mesh.lightmap_uvs.push_back(mesh.lightmap_uvs[from]);
  if (!mesh.tangents.empty()) mesh.tangents.push_back(mesh.tangents[from]);
  return uint32_t(mesh.positions.size() - 1);
}

bool zero_area_triangle(vec3 a, vec3 b, vec3 c) {
  constexpr float kDegenerateRatio = 1e-7f;
  const float longest =
      std::max({glm::dot(b - a, b - a), glm::dot(c - b, c - b), glm::dot(a - c, a - c)});
  return glm::length(glm::cross(b - a, c - a)) <= kDegenerateRatio * longest;
}

Mesh split_vertices(const Mesh& mesh, const VertexSplit& split) {
  Mesh out = mesh;
  if (split.empty()) return out;
  for (uint32_t from : split.copied_from) append_vertex_copy(out, from);
  out.triangles = split.triangles;
  return out;
}

}  // namespace lb
