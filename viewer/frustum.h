#pragma once
// View-frustum culling of axis-aligned boxes: the six planes of any world-to-clip matrix
// (a camera, a mirrored camera, a lamp's shadow matrix, a shadow cube face), so every pass
// skips what it cannot rasterise. Conservative: a box is culled only when it lies wholly
// outside one plane, so nothing a pass would draw is ever dropped.

#include <array>
#include <glm/glm.hpp>

#include "bake/scene.h"

namespace lb {

class Frustum {
 public:
  // Everything inside (culls nothing).
  Frustum() = default;
  // The region -w <= x, y, z <= w of clip = matrix * (p, 1) (Gribb and Hartmann, "Fast
  // Extraction of Viewing Frustum Planes from the World-View-Projection Matrix", 2001).
  explicit Frustum(const glm::mat4& world_to_clip);
  // Adds the half-space dot(plane.xyz, p) + plane.w >= 0 (a mirror pass's clip plane).
  void add_plane(glm::vec4 plane);
  // False only if the box lies wholly outside one plane, with a margin of 1e-5 of the box's
  // own size and distance so rounding in the test never drops a box the GL would draw.
  bool may_see(const Bounds& box) const;

 private:
  std::array<glm::vec4, 7> planes_{};
  int count_ = 0;
};

// The world-to-clip matrix of cube face `face` (+x, -x, +y, -y, +z, -z) around `centre`: the
// same mapping as shaders/shadows.glsl cube_face_clip_range.
glm::mat4 cube_face_matrix(vec3 centre, int face, float near, float far);

}  // namespace lb
