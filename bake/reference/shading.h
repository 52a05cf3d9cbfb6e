#pragma once
// What the reference's two tracers share: the context of a render and the local geometry of
// a hit (which side, which normals), decided by one rule for both so they count the same paths.

#include "bake/accel.h"
#include "bake/bump.h"
#include "bake/reference/light_set.h"
#include "bake/reference/reference.h"
#include "bake/surface.h"
#include "bake/thin_lens_camera.h"

namespace lb::reference {

struct Context {
  const Scene& scene;
  const Accel& accel;
  const ThinLensCamera& camera;
  const LightSet& lights;
  const ReferenceParams& params;
};

// A diffuse hit seen from the side `arrival` (direction of travel of the ray that found it):
// normals flipped to that side; the shading normal bump-mapped, and replaced by the geometric
// one if bumping tipped it below the surface.
struct DiffuseFrame {
  vec3 geometric_normal{0.0f};
  vec3 shading_normal{0.0f};
};
DiffuseFrame diffuse_frame(const Scene& scene, const SurfacePoint& sp, vec3 arrival);


}  // namespace lb::reference
