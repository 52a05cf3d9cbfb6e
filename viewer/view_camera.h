#pragma once
// The camera the viewer draws from: a pinhole at `position` looking at `target`. Orbit and
// fly controllers move it; scene cameras and fit-to-scene set it.
//
// Limits (issue 15): the orbit's pitch stays within +-kMaxOrbitPitchDeg, so the view never
// flips over the pole; given the scene's Accel, orbit and zoom keep the eye in front of the
// first surface that faces the target on the segment from the target to the eye (a floor seen
// from above, a room's inward walls), so the eye never goes through the floor or out of a
// room. Surfaces seen from behind (the inside of a ball the target sits in) do not stop it.

#include <glm/glm.hpp>

#include "bake/accel.h"
#include "bake/scene.h"

namespace lb {

inline constexpr float kMaxOrbitPitchDeg = 89.0f;

struct ViewCamera {
  vec3 position{0.0f, 0.0f, 5.0f};
  vec3 target{0.0f};
  vec3 up{0.0f, 1.0f, 0.0f};
  float vertical_fov_deg = 50.0f;
  // The eye's distance from the target that orbit and zoom keep, metres, when a surface pulled
  // the eye closer; 0: |position - target|. So the eye comes back out once the surface is
  // passed.
  float orbit_distance = 0.0f;

  static ViewCamera from(const Camera& camera);
  glm::mat4 view() const;
  // Near and far planes enclose `bounds` as seen from the camera.
  glm::mat4 projection(float aspect, const Bounds& bounds) const;
  vec3 forward() const { return glm::normalize(target - position); }
};

// Looks at the whole scene from the front (+z), a little above, with the given field of view.
// Given the accel, a closed room (room_enclosure() >= kClosedRoomFraction from the bounds'
// centre) is looked at from inside instead: the eye near the wall behind the centre on the
// longest horizontal axis, at the centre's height, looking at the centre.
ViewCamera fit_to_scene(const Bounds& bounds, float vertical_fov_deg = 50.0f,
                        const Accel* accel = nullptr);

// The fraction of kEnclosureDirections directions (a Fibonacci sphere, the same every call) in
// which a ray from `point` hits a surface facing it. 1 inside a closed room with inward
// faces; about 0.5 above a floor; 0 inside a closed object seen from behind (a ball) or in
// the open.
inline constexpr int kEnclosureDirections = 128;
inline constexpr float kClosedRoomFraction = 0.95f;  // a window or a door may let rays out
float room_enclosure(const Accel& accel, vec3 point);

// How far from `target` along unit `direction` the eye may stand: `wanted`, or in front of the
// first surface facing the target (by 2% of its distance, at least 1e-4 of the scene's size).
float unobstructed_distance(const Accel& accel, vec3 target, vec3 direction, float wanted);

// Orbit: yaw/pitch in radians about `target` (pitch within +-kMaxOrbitPitchDeg); zoom scales
// the distance. With an accel, the eye stops in front of surfaces (see above).
void orbit(ViewCamera& camera, float yaw, float pitch, const Accel* accel = nullptr);
void zoom(ViewCamera& camera, float factor, const Accel* accel = nullptr);
// The orbit's pitch, degrees: the eye's elevation above the target.
float orbit_pitch_deg(const ViewCamera& camera);
// Fly: move along forward/right/up in metres; look turns the view about the eye.
void fly(ViewCamera& camera, vec3 forward_right_up);
void look(ViewCamera& camera, float yaw, float pitch);

}  // namespace lb
