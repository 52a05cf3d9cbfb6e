#pragma once
// Arvo's splat: the power of each illumination path that ends on a diffuse surface goes to
// the four texel nodes around its hit with bilinear weights.

#include <cstdint>
#include <vector>

#include "bake/illumination/atlas.h"

namespace lb::illumination {

// Where an illumination path ended on a diffuse surface, and the power it carried there (W).
struct Deposit {
  uint32_t mesh = 0;
  uint32_t triangle = 0;
  vec2 barycentric{0.0f};
  vec3 power{0.0f};
};

// Arvo's splat of every deposit of `blocks` onto its four texel nodes, adding to `node_power`;
// returns the power that fell on meshes without a map. If `node_deposits` is given (same size),
// each deposit also adds its four bilinear weights to it: the deposit density that the
// density filter (density_filter.h) sizes its kernels by. Per group of blocks, node weights are
// found per block in parallel, then bands of nodes fill in parallel, each node adding its shares in
// block, deposit and corner order, the order of one sequential loop: the same bits whatever
// the thread count (and so the band count).
glm::dvec3 splat(const Atlas& atlas, const Scene& scene,
                 const std::vector<const std::vector<Deposit>*>& blocks,
                 std::vector<glm::dvec3>& node_power, std::vector<double>* node_deposits = nullptr);

}  // namespace lb::illumination
