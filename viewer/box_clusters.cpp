#include "viewer/box_clusters.h"

#include <algorithm>
#include <cmath>

namespace lb {

std::vector<BoxCluster> cluster_boxes(const std::vector<Bounds>& boxes, size_t per_cluster) {
  std::vector<BoxCluster> clusters;
  Bounds all;
  size_t count = 0;
  for (const Bounds& b : boxes) {
    if (b.empty()) continue;
    all.extend(0.5f * (b.min + b.max));
    ++count;
  }
  if (count == 0) return clusters;
  const vec3 extent = glm::max(all.extent(), vec3(1e-6f * std::max(all.diagonal(), 1e-3f)));
  const float cells = std::max(1.0f, float(count) / float(std::max<size_t>(1, per_cluster)));
  const float side = std::cbrt(extent.x * extent.y * extent.z / cells);
  glm::ivec3 dims;
  for (int a = 0; a < 3; ++a) dims[a] = std::clamp(int(std::ceil(extent[a] / side)), 1, 64);
  // A flat scene (a level's height) still gets kLayers cells across its thin axis when it has
  // boxes enough, the other two axes' cells growing to keep about as many in all: so a room's
  // furniture and the top of its walls fall in different clusters, and a cluster of furniture
  // can hide under the ceiling (viewer/occlusion_culler.h).
  constexpr int kLayers = 3;
  const int thin =
      extent.x <= extent.y && extent.x <= extent.z ? 0 : (extent.y <= extent.z ? 1 : 2);
  if (dims[thin] < kLayers && cells >= float(4 * kLayers)) {
    dims[thin] = kLayers;
    const int u = (thin + 1) % 3, v = (thin + 2) % 3;
    const float flat_side = std::sqrt(extent[u] * extent[v] / (cells / float(kLayers)));
    dims[u] = std::clamp(int(std::ceil(extent[u] / flat_side)), 1, 64);
    dims[v] = std::clamp(int(std::ceil(extent[v] / flat_side)), 1, 64);
  }
  std::vector<int> slot(size_t(dims.x * dims.y * dims.z), -1);
  for (size_t i = 0; i < boxes.size(); ++i) {
    const Bounds& b = boxes[i];
    if (b.empty()) continue;
    const vec3 t = (0.5f * (b.min + b.max) - all.min) / extent;
    glm::ivec3 c;
    for (int a = 0; a < 3; ++a) c[a] = std::clamp(int(t[a] * float(dims[a])), 0, dims[a] - 1);
    int& s = slot[size_t((c.z * dims.y + c.y) * dims.x + c.x)];
    if (s < 0) {
      s = int(clusters.size());
      clusters.emplace_back();
    }
    BoxCluster& cluster = clusters[size_t(s)];
    cluster.members.push_back(i);
    cluster.bounds.extend(b.min);
    cluster.bounds.extend(b.max);
  }
  return clusters;
}

float box_distance(const Bounds& box, vec3 p) {
  const vec3 outside = glm::max(glm::max(box.min - p, p - box.max), vec3(0.0f));
  return glm::length(outside);
}

}  // namespace lb
