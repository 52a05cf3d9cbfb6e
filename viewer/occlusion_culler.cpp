#include "viewer/occlusion_culler.h"

#include <algorithm>

#include "viewer/box_clusters.h"

namespace lb {

namespace {

// Clusters drawn first, untested (a light's own room and the next; the camera's own only), and
// the first tested batch; each batch is 4 times the one before, so a pass waits for query
// results a few times only (each wait drains llvmpipe's queue).
constexpr size_t kFirstDrawnCasters = 2, kFirstDrawnAll = 1;
constexpr size_t kFirstBatch = 16;
constexpr size_t kMeshesPerCluster = 24;

}  // namespace

OcclusionCuller::OcclusionCuller(const GpuScene& scene, Members members)
    : first_drawn_(members == Members::casters ? kFirstDrawnCasters : kFirstDrawnAll) {
  std::vector<size_t> kept;
  std::vector<Bounds> boxes;
  for (size_t m = 0; m < scene.meshes().size(); ++m) {
    const GpuMesh& mesh = scene.meshes()[m];
    if (mesh.index_count == 0 || mesh.bounds.empty()) continue;
    if (members == Members::casters &&
        scene.scene().materials[size_t(mesh.material)].is_emitter())
      continue;
    kept.push_back(m);
    boxes.push_back(mesh.bounds);
  }
  for (BoxCluster& c : cluster_boxes(boxes, kMeshesPerCluster)) {
    Cluster& cluster = clusters_.emplace_back();
    cluster.bounds = c.bounds;
    for (size_t i : c.members) {
      cluster.meshes.push_back(kept[i]);
      cluster.triangles += size_t(scene.meshes()[kept[i]].index_count / 3);
    }
  }
}

void OcclusionCuller::draw(const GpuScene& scene, const Frustum& frustum, vec3 eye,
                           float untested_within, GLenum depth_func, DrawCounts& counts,
                           std::vector<char>* drawn, const DetailView& detail) {
  if (drawn) drawn->assign(scene.meshes().size(), 0);
  queries_issued_ = 0;
  in_view_ = hidden_ = 0;
  auto skip = [&](const Cluster& cluster) {
    for (size_t m : cluster.meshes) scene.count_skipped(m, counts);
  };
  auto draw = [&](const Cluster& cluster) {
    for (size_t m : cluster.meshes) {
      if (drawn) (*drawn)[m] = 1;
      if (!scene.culled(m, frustum, counts)) scene.draw_mesh(m, frustum, counts, detail);
    }
  };
  std::vector<std::pair<float, size_t>> order;
  for (size_t c = 0; c < clusters_.size(); ++c) {
    if (!frustum.may_see(clusters_[c].bounds)) {
      skip(clusters_[c]);
      continue;
    }
    order.emplace_back(box_distance(clusters_[c].bounds, eye), c);
    in_view_ += clusters_[c].triangles;
  }
  std::sort(order.begin(), order.end());
  const size_t first = std::min(order.size(), first_drawn_);
  for (size_t i = 0; i < first; ++i) draw(clusters_[order[i].second]);
  // Boxes grow by a margin so that they cover every pixel their meshes do and lie in front of
  // them, whatever the rounding (1e-4 of the scene, 1 cm on a 100 m level).
  const float margin = 1e-4f * std::max(scene.bounds().diagonal(), 1e-3f);
  std::vector<Bounds> boxes;
  std::vector<size_t> tested;
  std::vector<char> visible, answers;
  size_t batch = kFirstBatch;
  for (size_t begin = first; begin < order.size(); begin += batch, batch *= 4) {
    const size_t end = std::min(order.size(), begin + batch);
    boxes.clear();
    tested.clear();
    for (size_t i = begin; i < end; ++i) {
      if (order[i].first <= untested_within + margin) continue;  // the near plane may clip it
      const Bounds& b = clusters_[order[i].second].bounds;
      boxes.push_back({b.min - vec3(margin), b.max + vec3(margin)});
      tested.push_back(i);
    }
    queries_.test(boxes, depth_func, answers);
    queries_issued_ += int(boxes.size());
    visible.assign(end - begin, 1);
    for (size_t j = 0; j < tested.size(); ++j) visible[tested[j] - begin] = answers[j];
    for (size_t i = begin; i < end; ++i) {
      const Cluster& cluster = clusters_[order[i].second];
      if (visible[i - begin]) {
        draw(cluster);
      } else {
        skip(cluster);
        hidden_ += cluster.triangles;
      }
    }
  }
  glBindVertexArray(0);
}

}  // namespace lb
