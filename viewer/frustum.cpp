#include "viewer/frustum.h"

#include <cmath>

namespace lb {

Frustum::Frustum(const glm::mat4& m) {
  // glm is column-major: row r of the matrix is (m[0][r], m[1][r], m[2][r], m[3][r]).
  auto row = [&](int r) { return glm::vec4(m[0][r], m[1][r], m[2][r], m[3][r]); };
  const glm::vec4 w = row(3);
  for (int r = 0; r < 3; ++r) {
    add_plane(w + row(r));  // -w <= clip[r]
    add_plane(w - row(r));  // clip[r] <= w
  }
}

void Frustum::add_plane(glm::vec4 plane) {
  if (count_ < int(planes_.size())) planes_[size_t(count_++)] = plane;
}

bool Frustum::may_see(const Bounds& box) const {
  if (box.empty()) return false;
  const vec3 centre = 0.5f * (box.min + box.max), half = 0.5f * (box.max - box.min);
  for (int i = 0; i < count_; ++i) {
    const glm::vec4& p = planes_[size_t(i)];
    const vec3 n(p);
    // The box corner farthest along n, and the scale of the terms that make up its distance.
    const float reach = std::abs(n.x) * half.x + std::abs(n.y) * half.y + std::abs(n.z) * half.z;
    const float distance = glm::dot(n, centre) + p.w + reach;
    const float scale = std::abs(glm::dot(glm::abs(n), glm::abs(centre))) + std::abs(p.w) + reach;
    if (distance < -1e-5f * scale) return false;
  }
  return true;
}

glm::mat4 cube_face_matrix(vec3 centre, int face, float near, float far) {
  const int axis = face / 2;
  const float sign = (face % 2 == 0) ? 1.0f : -1.0f;
  const int second = (axis + 1) % 3, third = (axis + 2) % 3;
  const float a = (far + near) / (far - near), b = -2.0f * far * near / (far - near);
  // clip = (d[second], d[third], a m + b, m), m = sign d[axis], d = p - centre.
  glm::mat4 m(0.0f);  // m[column][row]
  m[second][0] = 1.0f;
  m[third][1] = 1.0f;
  m[axis][2] = a * sign;
  m[axis][3] = sign;
  m[3][0] = -centre[second];
  m[3][1] = -centre[third];
  m[3][2] = -a * sign * centre[axis] + b;
  m[3][3] = -sign * centre[axis];
  return m;
}

}  // namespace lb
