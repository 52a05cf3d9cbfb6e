#pragma once
// Density-estimation filter of the caustic map (issue 11): after Arvo's splat each node holds
// the power of the deposits around it, and where deposits are sparse (a caustic's faint halo,
// glossy scatter) that power is speckled: a node's value is the mean of a handful of random
// paths. Each node therefore spreads its power over a disk of nodes whose radius is chosen so
// that the disk holds about `min_deposits` deposits at the local deposit density
// (k-nearest-neighbour density estimation, Silverman 1986; Jensen's photon maps gather the
// same way): where deposits are dense the radius is below one texel and the caustic stays as
// sharp as the map; where they are sparse it grows up to `max_radius` texels and the speckle
// averages out.
//
// Estimator: each node's radiance becomes the kernel-weighted mean radiance of its chart's
// nodes within its radius, weighted by node area (a gather, so a uniform radiance stays
// exactly uniform, at chart borders too); nothing crosses a chart border (another wall, the
// other side of a crease). Kernel: Epanechnikov, 1 - (d / R)^2 for node distances d < R
// (texels). Energy: each chart's filtered power is scaled back to its power before the
// filter, so the map holds exactly the deposited power (to rounding); the scale differs from
// 1 only by how much the chart's light moves against its border (measured below 1e-3).
//
// Determinism: every node reads only the unfiltered map, and the chart sums run in node
// order; the same bits whatever the thread count.

#include <glm/glm.hpp>
#include <vector>

#include "bake/illumination/atlas.h"

namespace lb::illumination {

struct DensityFilterStats {
  size_t nodes_lit = 0;      // nodes with power before the filter
  size_t nodes_spread = 0;   // of those, nodes whose kernel reached other nodes (R > 1)
  double mean_radius = 0.0;  // kernel radius R, texels, over lit nodes, weighted by power
  double power = 0.0;        // W, summed over the lit nodes and the three channels
};

// `node_deposits`: per node, the sum of the bilinear weights of the deposits splatted on it
// (splat's count). `node_power` (W per node) is replaced by its filtered version. Charts of the
// meshes m with `raw_meshes[m]` set keep their raw splat (the bake: meshes whose texels the
// caustic pilot refined, illumination.h).
DensityFilterStats filter_by_density(const Atlas& atlas, const std::vector<double>& node_deposits,
                                     double min_deposits, int max_radius,
                                     std::vector<glm::dvec3>& node_power,
                                     const std::vector<bool>& raw_meshes = {});

}  // namespace lb::illumination
