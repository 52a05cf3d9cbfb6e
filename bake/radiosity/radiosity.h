#pragma once
// Pass 2: soft indirect light by ray-traced progressive shooting (Shirley 1990, section 3.2).
// Light is shot from each emitter first and the power it deposits is kept as unsent but not
// counted, so only light that met two or more diffuse surfaces remains in the result.

#include <cstdint>

#include "bake/accel.h"
#include "bake/bake_result.h"
#include "bake/progress.h"

namespace lb {

struct RadiosityParams {
  // Target patch edge, metres; 0 = automatic from the scene's scale (about 32 patches on a
  // typical wall, as in the paper). Meshes' own bake settings take precedence.
  float patch_size = 0.0f;
  // Rays per watt... see radiosity.cpp; total rays for the whole solve, spread over shots in
  // proportion to the power each shot carries.
  uint64_t ray_budget = 2'000'000;
  // Stop when the unsent power falls below this fraction of the emitted power.
  double convergence = 1e-3;
  // Hard cap on shots, so albedo near 1 cannot run forever.
  uint64_t max_shots = 100'000;
  uint64_t seed = 1;
};

VertexRadiosity solve_radiosity(const Scene& scene, const Accel& accel,
                                const RadiosityParams& params, const Progress& progress = {});

}  // namespace lb
