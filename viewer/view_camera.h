#pragma once
// The camera the viewer draws from: a pinhole at `position` looking at `target`. Orbit and
// fly controllers move it; scene cameras and fit-to-scene set it.

#include <glm/glm.hpp>

#include "bake/scene.h"

namespace lb {

struct ViewCamera {
  vec3 position{0.0f, 0.0f, 5.0f};
  vec3 target{0.0f};
  vec3 up{0.0f, 1.0f, 0.0f};
  float vertical_fov_deg = 50.0f;

  static ViewCamera from(const Camera& camera);
  glm::mat4 view() const;
  // Near and far planes enclose `bounds` as seen from the camera.
  glm::mat4 projection(float aspect, const Bounds& bounds) const;
  vec3 forward() const { return glm::normalize(target - position); }
};

// Looks at the whole scene from the front (+z), a little above, with the given field of view.
ViewCamera fit_to_scene(const Bounds& bounds, float vertical_fov_deg = 50.0f);

// Orbit: yaw/pitch in radians about `target`; zoom scales the distance.
void orbit(ViewCamera& camera, float yaw, float pitch);
void zoom(ViewCamera& camera, float factor);
// Fly: move along forward/right/up in metres; look turns the view about the eye.
void fly(ViewCamera& camera, vec3 forward_right_up);
void look(ViewCamera& camera, float yaw, float pitch);

}  // namespace lb
