#pragma once
// The soft-light map's correction filter (soft_texels.h): the weight-averaged mean of a
// node's neighbours within a box, never mixing charts. Box sums come from per-chart
// summed-area tables (double precision, fixed order: the bits do not depend on the thread
// count), so a wide box costs what a narrow one does.
//
// Radii may differ per node (soft_texels.h narrows them near contacts, where the correction
// changes fast). Two nodes then average each other only within both of their radii: the kernel
// stays symmetric, so a wide box does not take in the sharp correction of a narrow node beside
// it, which that node already holds (a plain box per node counted it twice: measured on the
// Cornell box, 1.7x the correction's own power change; bench/results/LOG.md).

#include <glm/glm.hpp>
#include <span>
#include <vector>

namespace lb {

using glm::vec3;

// Chart labels: 4-connected components of the nodes with weight > 0 (the atlas pads charts
// apart, so each component is one chart), -1 elsewhere.
std::vector<int> label_charts(int width, int height, const std::vector<double>& weight);

// The weight-averaged mean of `values` over the nodes of the same chart within `radius`
// texels (a (2 radius + 1)^2 box clipped to the chart); 0 where weight is 0.
std::vector<vec3> chart_box_filter(int width, int height, const std::vector<vec3>& values,
                                   const std::vector<double>& weight, int radius);

// The same with a radius of its own at each node (`radius[k]` >= 0, width*height): node k's
// value is the weight-averaged mean of the chart's nodes n within min(radius[k], radius[n])
// of it. Costs one summed-area table per distinct radius in a chart.
std::vector<vec3> chart_box_filter(int width, int height, const std::vector<vec3>& values,
                                   const std::vector<double>& weight,
                                   const std::vector<int>& radius);

// What a node takes from its box. `mean`: the nodes' weighted mean, which belongs to the box's
// centroid: the node itself where the box is whole and even, a point inside the chart where
// the chart's border cuts the box (or a neighbour's narrower radius leaves it out), where a
// field changing towards the border (the darkening into a crease) is then misplaced.
// `mean_at_node`: that mean moved to the node along the slope of the least-squares plane
// through the nodes within twice the radius (the same nodes' rule, doubled).
enum class ChartFit { mean, mean_at_node };

// The same for several layers on the same weights (light groups' maps), each overwritten by
// its filtered values: the charts are found once for all layers.
void chart_box_filter_in_place(int width, int height, std::span<std::vector<vec3>* const> layers,
                               const std::vector<double>& weight, const std::vector<int>& radius,
                               ChartFit fit = ChartFit::mean);

}  // namespace lb
