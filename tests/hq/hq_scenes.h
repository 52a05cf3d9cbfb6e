#pragma once
// Scenes for the HQ renderer's tests and benchmarks, built in code.

#include "bake/bake_result.h"
#include "bake/scene.h"

namespace lb::test {

// A 6 x 3 x 6 m room (floor y = 0, reflectance 0.6) with a grid of `per_side` x `per_side`
// square ceiling lights (0.5 m, radiance 5 W/(sr m^2), facing down, just below the ceiling)
// and a 2 x 2 m table top at 0.9..1.0 m that casts partial shadows. per_side = 3 is the paper's
// Figure 5 arrangement of nine lights. The total emitted power is the same for any per_side.
Scene make_light_grid_room(int per_side = 3);

// A baked scene with no baked light (empty maps, no radiosity), for direct-light-only tests.
BakedScene unbaked(const Scene& scene);

}  // namespace lb::test
