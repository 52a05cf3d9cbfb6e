#include "bake/io/uv_transform.h"

#include <cmath>

namespace lb {

glm::dmat3 uv_transform_matrix(glm::dvec2 offset, double rotation, glm::dvec2 scale) {
  const double c = std::cos(rotation), s = std::sin(rotation);
  // glm is column-major: each line below is one column.
  const glm::dmat3 translate(1, 0, 0, 0, 1, 0, offset.x, offset.y, 1);
  const glm::dmat3 rotate(c, -s, 0, s, c, 0, 0, 0, 1);
  const glm::dmat3 scaling(scale.x, 0, 0, 0, scale.y, 0, 0, 0, 1);
  return translate * rotate * scaling;
}

glm::vec2 apply_uv_transform(const glm::dmat3& matrix, glm::vec2 uv) {
  const glm::dvec3 result = matrix * glm::dvec3(uv.x, uv.y, 1.0);
  return glm::vec2(float(result.x), float(result.y));
}

}  // namespace lb
