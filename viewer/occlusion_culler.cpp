#include "viewer/occlusion_culler.h"

#include <algorithm>

#include "viewer/alpha_cut.h"
#include "viewer/box_clusters.h"

namespace lb {

namespace {

// Clusters drawn first, untested (a light's own room and the next; the camera's own only), and
// the first tested batch; each batch is 4 times the one before, so a pass waits for query
// results a few times only (each wait drains llvmpipe's queue).
constexpr size_t kFirstDrawnCasters = 2, kFirstDrawnAll = 1;
constexpr size_t kFirstBatch = 16;
constexpr size_t kMeshesPerCluster = 24;
// Occluders: meshes of at most this many triangles whose box is at least kOccluderSize long
// (walls and their pieces, floors, ceilings, panels, boards). A cluster whose box shows draws
// its occluders first and is tested again without them, so a room's ceiling and walls can hide
// what stands in it: a cluster, a cell of the grid, may hold both, and its box reaches the
// ceiling. Every piece counts: a wall's top left out would let the boxes below it show through
// between the ceilings.
constexpr size_t kOccluderTriangles = 12;
constexpr float kOccluderSize = 0.75f;  // m

bool is_occluder(const GpuMesh& mesh) {
  const size_t triangles = size_t(mesh.index_count / 3);
  const vec3 e = mesh.bounds.extent();
  return triangles > 0 && triangles <= kOccluderTriangles &&
         std::max({e.x, e.y, e.z}) >= kOccluderSize;
}

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
    if (alpha_cut(scene, m)) continue;  // not an occluder; drawn by its pass (alpha_cut.h)
    kept.push_back(m);
    boxes.push_back(mesh.bounds);
  }
  for (BoxCluster& c : cluster_boxes(boxes, kMeshesPerCluster)) {
    Cluster& cluster = clusters_.emplace_back();
    cluster.bounds = c.bounds;
    for (size_t i : c.members) {
      const GpuMesh& mesh = scene.meshes()[kept[i]];
      cluster.meshes.push_back(kept[i]);
      cluster.triangles += size_t(mesh.index_count / 3);
      if (is_occluder(mesh)) {
        cluster.occluders.push_back(kept[i]);
      } else {
        cluster.others.push_back(kept[i]);
        cluster.others_bounds.extend(mesh.bounds.min);
        cluster.others_bounds.extend(mesh.bounds.max);
      }
    }
  }
}

void OcclusionCuller::draw(const GpuScene& scene, const Frustum& frustum, vec3 eye,
                           float untested_within, GLenum depth_func, DrawCounts& counts,
                           std::vector<char>* drawn, const DetailView& detail) {
  if (drawn) drawn->assign(scene.meshes().size(), 0);
  queries_issued_ = 0;
  in_view_ = hidden_ = 0;
  auto skip = [&](const std::vector<size_t>& meshes) {  // returns the triangles it skipped
    size_t triangles = 0;
    for (size_t m : meshes) {
      scene.count_skipped(m, counts);
      triangles += size_t(scene.meshes()[m].index_count / 3);
    }
    return triangles;
  };
  auto draw = [&](const std::vector<size_t>& meshes) {
    for (size_t m : meshes) {
      if (drawn) (*drawn)[m] = 1;
      if (!scene.culled(m, frustum, counts)) scene.draw_mesh(m, frustum, counts, detail);
    }
  };
  std::vector<std::pair<float, size_t>> order;
  distance_.assign(clusters_.size(), 0.0f);
  for (size_t c = 0; c < clusters_.size(); ++c) {
    if (!frustum.may_see(clusters_[c].bounds)) {
      skip(clusters_[c].meshes);
      continue;
    }
    distance_[c] = box_distance(clusters_[c].bounds, eye);
    order.emplace_back(distance_[c], c);
    in_view_ += clusters_[c].triangles;
  }
  std::sort(order.begin(), order.end());
  const size_t first = std::min(order.size(), first_drawn_);
  for (size_t i = 0; i < first; ++i) draw(clusters_[order[i].second].meshes);
  // Boxes grow by a margin so that they cover every pixel their meshes do and lie in front of
  // them, whatever the rounding (1e-4 of the scene, 1 cm on a 100 m level).
  const float margin = 1e-4f * std::max(scene.bounds().diagonal(), 1e-3f);
  std::vector<Bounds> boxes;
  std::vector<size_t> tested;
  std::vector<char> answers;
  // Tests `items` (indices of clusters_) against the depth drawn so far, each with its whole
  // box or that of its members but the occluders (`others`; none: nothing left, it shows);
  // items within `untested_within` of the eye show untested (the near plane may clip them).
  // shows[k] for items[k].
  std::vector<char> shows;
  auto test = [&](const std::vector<size_t>& items, bool others) {
    boxes.clear();
    tested.clear();
    shows.assign(items.size(), 1);
    for (size_t k = 0; k < items.size(); ++k) {
      if (distance_[items[k]] <= untested_within + margin) continue;
      const Bounds& b = others ? clusters_[items[k]].others_bounds : clusters_[items[k]].bounds;
      if (b.empty()) continue;
      boxes.push_back({b.min - vec3(margin), b.max + vec3(margin)});
      tested.push_back(k);
    }
    queries_.test(boxes, depth_func, answers);
    queries_issued_ += int(boxes.size());
    for (size_t j = 0; j < tested.size(); ++j) shows[tested[j]] = answers[j];
  };
  // The other clusters, nearest first, in batches of kFirstBatch and 4 times more each time.
  // With occluders first, a batch's clusters that show draw their occluders, and then each is
  // tested again with the box of its other members: a ceiling hides what stands under it
  // though its cluster's box reaches it.
  std::vector<size_t> batch_items, again;
  size_t batch = kFirstBatch;
  for (size_t begin = first; begin < order.size(); begin += batch, batch *= 4) {
    const size_t end = std::min(order.size(), begin + batch);
    batch_items.clear();
    for (size_t i = begin; i < end; ++i) batch_items.push_back(order[i].second);
    test(batch_items, false);
    again.clear();
    for (size_t k = 0; k < batch_items.size(); ++k) {
      const Cluster& cluster = clusters_[batch_items[k]];
      if (!shows[k]) {
        hidden_ += skip(cluster.meshes);
      } else if (occluders_first_ && !cluster.occluders.empty()) {
        draw(cluster.occluders);
        again.push_back(batch_items[k]);
      } else {
        draw(cluster.meshes);
      }
    }
    if (again.empty()) continue;
    test(again, true);
    for (size_t k = 0; k < again.size(); ++k) {
      const Cluster& cluster = clusters_[again[k]];
      if (shows[k]) {
        draw(cluster.others);
      } else {
        hidden_ += skip(cluster.others);
      }
    }
  }
  glBindVertexArray(0);
}

}  // namespace lb
