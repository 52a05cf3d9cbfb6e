#pragma once
// The receiver at a footprint point, for the estimators that fill texels with rays (direct
// light, final gather): the front side of the surface, the interpolated vertex normal for the
// cosine where the mesh has normals on that side, the geometric normal otherwise.

#include "bake/transport/direct_light.h"
#include "bake/lightmap/texel_footprint.h"

namespace lb {

inline ReceiverPoint receiver_at_sample(const Mesh& mesh, const FootprintSample& p) {
  ReceiverPoint x;
  x.position = p.position;
  x.geometric_normal = p.normal;
  x.shading_normal = p.normal;
  if (mesh.normals.size() == mesh.positions.size()) {
    const uvec3 tri = mesh.triangles[p.triangle];
    const float b1 = p.barycentric.x, b2 = p.barycentric.y, b0 = 1.0f - b1 - b2;
    const vec3 n_s = b0 * mesh.normals[tri.x] + b1 * mesh.normals[tri.y] + b2 * mesh.normals[tri.z];
    const float length = glm::length(n_s);
    if (length > 0.0f && glm::dot(n_s, p.normal) > 0.0f) x.shading_normal = n_s / length;
  }
  return x;
}

}  // namespace lb
