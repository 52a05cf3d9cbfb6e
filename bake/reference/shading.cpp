#include "bake/reference/shading.h"

#include <algorithm>

#include "bake/bump.h"

namespace lb::reference {

DiffuseFrame diffuse_frame(const Scene& scene, const SurfacePoint& sp, vec3 arrival) {
  const float side = glm::dot(arrival, sp.geometric_normal) < 0.0f ? 1.0f : -1.0f;
  DiffuseFrame frame;
  frame.geometric_normal = side * sp.geometric_normal;
  frame.shading_normal = side * bumped_normal(scene, sp);
  if (glm::dot(frame.shading_normal, frame.geometric_normal) <= 0.0f)
    frame.shading_normal = frame.geometric_normal;
  return frame;
}

}  // namespace lb::reference
