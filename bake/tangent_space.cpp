#include "bake/tangent_space.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <map>
#include <utility>

namespace lb {

namespace {

struct Corner {
  vec3 tangent{0.0f};  // dP/du projected into the corner's tangent plane, unit (or zero)
  vec3 normal{0.0f};
  float angle = 0.0f;
  int orientation = 0;  // +1 keeps the winding (w = +1), -1 mirrors it, 0 degenerate UVs
  int group = -1;
};

vec3 project_unit(vec3 v, vec3 n) {
  const vec3 p = v - n * glm::dot(n, v);
  const float length = glm::length(p);
  return length > 0.0f ? p / length : vec3(0.0f);
}

vec3 any_perpendicular(vec3 n) {
  return glm::normalize(glm::cross(std::abs(n.x) < 0.9f ? vec3(1, 0, 0) : vec3(0, 1, 0), n));
}

}  // namespace

void generate_mikktspace_tangents(Mesh& mesh) {
  if (mesh.uvs.empty()) return;
  const size_t triangle_count = mesh.triangles.size();
  std::vector<Corner> corners(triangle_count * 3);

  // Welded vertex ids: corners with equal position, normal and uv share one.
  using Key = std::array<float, 8>;
  std::map<Key, int> weld;
  std::vector<int> welded(corners.size());

  for (size_t t = 0; t < triangle_count; ++t) {
    const uvec3 tri = mesh.triangles[t];
    const vec3 p[3] = {mesh.positions[tri.x], mesh.positions[tri.y], mesh.positions[tri.z]};
    const vec2 uv[3] = {mesh.uvs[tri.x], mesh.uvs[tri.y], mesh.uvs[tri.z]};
    const vec3 d1 = p[1] - p[0], d2 = p[2] - p[0];
    const vec2 t1 = uv[1] - uv[0], t2 = uv[2] - uv[0];
    const vec3 face_normal = glm::cross(d1, d2);
    const float face_length = glm::length(face_normal);
    // UV area x 2 in glTF's frame (v down); the map's frame has v up, which flips its sign.
    const float uv_area = t1.x * t2.y - t1.y * t2.x;
    // dP/du x uv_area; its direction is dP/du's when uv_area > 0.
    const vec3 scaled_dp_du = d1 * t2.y - d2 * t1.y;
    const bool degenerate = !(std::abs(uv_area) > 0.0f) || glm::length(scaled_dp_du) == 0.0f;
    const vec3 dp_du = degenerate ? vec3(0.0f) : scaled_dp_du * (uv_area > 0.0f ? 1.0f : -1.0f);
    const int orientation = degenerate ? 0 : (uv_area < 0.0f ? 1 : -1);
    for (int k = 0; k < 3; ++k) {
      Corner& c = corners[t * 3 + size_t(k)];
      const uint32_t v = tri[k];
      c.normal = !mesh.normals.empty() ? mesh.normals[v]
                 : face_length > 0.0f  ? face_normal / face_length
                                       : vec3(0, 0, 1);
      c.orientation = orientation;
      c.tangent = project_unit(dp_du, c.normal);
      const vec3 e1 = project_unit(p[(k + 1) % 3] - p[k], c.normal);
      const vec3 e2 = project_unit(p[(k + 2) % 3] - p[k], c.normal);
      c.angle = std::acos(std::clamp(glm::dot(e1, e2), -1.0f, 1.0f));
      const Key key = {p[k].x,     p[k].y,     p[k].z,  c.normal.x,
                       c.normal.y, c.normal.z, uv[k].x, uv[k].y};
      welded[t * 3 + size_t(k)] = weld.emplace(key, int(weld.size())).first->second;
    }
  }

  // Groups: (welded vertex, orientation); sums of angle-weighted corner tangents.
  std::map<std::pair<int, int>, int> group_of;
  std::vector<vec3> sums;
  std::vector<int> group_orientation;
  for (size_t i = 0; i < corners.size(); ++i) {
    Corner& c = corners[i];
    if (c.orientation == 0) continue;
    auto [it, added] = group_of.emplace(std::make_pair(welded[i], c.orientation), int(sums.size()));
    if (added) {
      sums.push_back(vec3(0.0f));
      group_orientation.push_back(c.orientation);
    }
    c.group = it->second;
    sums[size_t(c.group)] += c.tangent * c.angle;
  }
  // Degenerate-UV corners join a group of their welded vertex (mirrored first, if both exist).
  std::map<int, int> any_group_of_vertex;
  for (const auto& [key, group] : group_of) any_group_of_vertex.emplace(key.first, group);
  for (size_t i = 0; i < corners.size(); ++i)
    if (corners[i].group < 0)
      if (auto found = any_group_of_vertex.find(welded[i]); found != any_group_of_vertex.end())
        corners[i].group = found->second;

  // Per corner result, then vertices split where corners of one vertex disagree.
  const size_t vertex_count = mesh.positions.size();
  mesh.tangents.assign(vertex_count, vec4(0.0f));
  std::vector<bool> assigned(vertex_count, false);
  std::map<std::pair<uint32_t, std::array<float, 4>>, uint32_t> copies;
  for (size_t i = 0; i < corners.size(); ++i) {
    const Corner& c = corners[i];
    vec4 result(any_perpendicular(c.normal), 1.0f);
    if (c.group >= 0) {
      const vec3 sum = sums[size_t(c.group)];
      const float length = glm::length(sum);
      result = vec4(length > 0.0f ? sum / length : any_perpendicular(c.normal),
                    float(group_orientation[size_t(c.group)]));
    }
    uint32_t& index = mesh.triangles[i / 3][int(i % 3)];
    const uint32_t original = index;
    const std::array<float, 4> value = {result.x, result.y, result.z, result.w};
    if (!assigned[original]) {
      assigned[original] = true;
      mesh.tangents[original] = result;
      copies.emplace(std::make_pair(original, value), original);
      continue;
    }
    auto [it, added] = copies.emplace(std::make_pair(original, value), 0u);
    if (added) {
      it->second = append_vertex_copy(mesh, original);
      mesh.tangents[it->second] = result;
    }
    index = it->second;
  }
  for (size_t v = 0; v < vertex_count; ++v)
    if (!assigned[v])  // not used by any triangle
      mesh.tangents[v] =
          vec4(any_perpendicular(mesh.normals.empty() ? vec3(0, 0, 1) : mesh.normals[v]), 1.0f);
}

}  // namespace lb
