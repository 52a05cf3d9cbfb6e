#pragma once
// The soft-light map's correction filter (soft_texels.h): the weight-averaged mean of a
// node's neighbours within a box, never mixing charts. Box sums come from per-chart
// summed-area tables (double precision, fixed order: the bits do not depend on the thread
// count), so a wide box costs what a narrow one does.
//
// A box whose radius adapts per node (intersection of confidence intervals) was tried on the
// Cornell box and measured no better than a fixed one (docs/speed-accuracy.md, "The soft-light
// texel map"): the correction's error there is its noise, not smear at contacts.

#include <glm/glm.hpp>
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

}  // namespace lb
