#pragma once
// Small helpers shared by the reference renderer's tests.

#include "bake/accel.h"
#include "bake/reference/reference.h"

namespace lb::reference {

// A render of `params.spp` passes (its own accelerator).
inline Film render(const Scene& scene, const Camera& camera, const ReferenceParams& params) {
  const Accel accel(scene);
  const ReferenceRenderer renderer(scene, accel, camera, params);
  ReferenceStats stats;
  return renderer.render(stats);
}

// The RGB mean, the grey value the tests compare.
inline double grey(vec3 v) {
  return (double(v.x) + double(v.y) + double(v.z)) / 3.0;
}

}  // namespace lb::reference
