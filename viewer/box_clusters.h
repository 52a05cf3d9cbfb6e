#pragma once
// Axis-aligned boxes grouped by a uniform grid over their centres, about `per_cluster` a
// cell (on a level of rooms the cells are about its rooms): one box test per cluster stands
// for its members' (viewer/occlusion_culler.h, viewer/light_lists.h).

#include <vector>

#include "bake/scene.h"

namespace lb {

struct BoxCluster {
  Bounds bounds;                // of its members' boxes
  std::vector<size_t> members;  // indices into the boxes given, ascending
};

// Empty boxes belong to no cluster. Clusters in the order their first member appears.
std::vector<BoxCluster> cluster_boxes(const std::vector<Bounds>& boxes, size_t per_cluster);

// Distance (m) from p to the nearest point of `box`; 0 inside.
float box_distance(const Bounds& box, vec3 p);

}  // namespace lb
