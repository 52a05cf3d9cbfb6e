#pragma once
// Choosing a view: the scene's cameras by name or index, or one that frames the scene.
// Shared by every front end so `--camera` means the same thing in snapshot, view and render.

#include <string>

#include "bake/scene.h"

namespace lb {

// Frames `bounds` from the +z side, a little above, with the whole box in view.
Camera fit_camera(const Bounds& bounds, float vertical_fov_deg = 50.0f);

// "" picks the scene's first camera (or a fitted one if it has none); otherwise a camera
// name, an index, or "fit". Throws std::invalid_argument listing the scene's cameras.
Camera select_camera(const Scene& scene, const std::string& name_or_index);

}  // namespace lb
