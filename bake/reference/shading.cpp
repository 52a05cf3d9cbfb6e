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

bool survive_roulette(vec3& throughput, float threshold, float u) {
  const float strength = std::max({throughput.x, throughput.y, throughput.z});
  if (!(strength > 0.0f)) return false;
  if (strength >= threshold) return true;
  const float survive = strength / threshold;
  if (u >= survive) return false;
  throughput /= survive;
  return true;
}

}  // namespace lb::reference
