#pragma once
// Arvo's splat: the power of each illumination path that ends on a diffuse surface goes to
// the four texel nodes around its hit with bilinear weights, as the path arrives, straight into
// pass 1's fixed-point sums (fixed_sums.h): no list of deposits is kept, and the order in which
// threads add does not change a bit.

#include <array>
#include <cstdint>

#include "bake/illumination/atlas.h"
#include "bake/illumination/fixed_sums.h"

namespace lb::illumination {

// Adds `power` (W) at the surface point to its four nodes' power, and the four bilinear
// weights to their deposit weight (the density filter's count, density_filter.h). Safe to call
// from many threads at once. Returns false, adding nothing, when the mesh has no map. `group`
// >= 0: the same units go to that light group's sums too (Pass1Sums::group_power). `l1`
// (with Pass1Sums::node_l1): the deposit's L1 power per world axis (l1_of_sample of the power),
// splatted with the same weights.
bool splat_deposit(const Atlas& atlas, const Scene& scene, const FixedScale& scale, uint32_t mesh,
                   uint32_t triangle, vec2 barycentric, vec3 power, Pass1Sums& sums,
                   int group = -1, const std::array<vec3, 3>* l1 = nullptr);

}  // namespace lb::illumination
