#include "bake/box_grid.h"

#include <algorithm>
#include <cmath>

namespace lb {

BoxGrid::BoxGrid(std::vector<vec3> low, std::vector<vec3> high)
    : low_(std::move(low)), high_(std::move(high)) {
  Bounds bounds;
  size_t count = 0;
  for (size_t i = 0; i < low_.size(); ++i) {
    if (glm::any(glm::greaterThan(low_[i], high_[i]))) continue;
    bounds.extend(low_[i]);
    bounds.extend(high_[i]);
    ++count;
  }
  if (count == 0) return;
  // About one cell per box, cells as near cubes as the bounds allow (a flat level gets one
  // layer); a zero extent gets one cell.
  const vec3 extent = bounds.extent();
  const float largest = std::max({extent.x, extent.y, extent.z});
  if (largest > 0.0f) {
    const double volume_cells = double(count);
    vec3 relative = extent / largest;
    // Extents below 1/count of the largest count as flat.
    relative = glm::max(relative, vec3(1.0f / float(count)));
    const double scale = std::cbrt(volume_cells / (double(relative.x) * relative.y * relative.z));
    for (int a = 0; a < 3; ++a)
      dims_[a] = int(std::clamp(std::floor(double(relative[a]) * scale), 1.0, 1024.0));
    for (int a = 0; a < 3; ++a)
      inverse_cell_[a] = extent[a] > 0.0f ? float(dims_[a]) / extent[a] : 0.0f;
  }
  origin_ = bounds.min;

  const size_t cells = size_t(dims_.x) * dims_.y * dims_.z;
  cell_start_.assign(cells + 1, 0);
  // Two passes (count, then fill) over the boxes' cell ranges, in id order, so each cell's
  // list is ascending.
  auto for_cells = [&](uint32_t id, auto&& visit) {
    const glm::ivec3 a = cell_of(low_[id]), b = cell_of(high_[id]);
    for (int z = a.z; z <= b.z; ++z)
      for (int y = a.y; y <= b.y; ++y)
        for (int x = a.x; x <= b.x; ++x) visit((size_t(z) * dims_.y + y) * dims_.x + x);
  };
  std::vector<uint8_t> is_large(low_.size(), 0);
  for (uint32_t id = 0; id < low_.size(); ++id) {
    if (glm::any(glm::greaterThan(low_[id], high_[id]))) continue;
    const glm::ivec3 span = cell_of(high_[id]) - cell_of(low_[id]) + 1;
    if (int64_t(span.x) * span.y * span.z > kMaxCellsPerBox) {
      is_large[id] = 1;
      large_.push_back(id);
      continue;
    }
    for_cells(id, [&](size_t c) { ++cell_start_[c + 1]; });
  }
  for (size_t c = 0; c < cells; ++c) cell_start_[c + 1] += cell_start_[c];
  ids_.resize(cell_start_[cells]);
  std::vector<uint32_t> fill(cell_start_.begin(), cell_start_.end() - 1);
  for (uint32_t id = 0; id < low_.size(); ++id) {
    if (is_large[id] || glm::any(glm::greaterThan(low_[id], high_[id]))) continue;
    for_cells(id, [&](size_t c) { ids_[fill[c]++] = id; });
  }
}

glm::ivec3 BoxGrid::cell_of(vec3 p) const {
  glm::ivec3 cell;
  for (int a = 0; a < 3; ++a) {
    // Monotone in p (clamping included): overlapping boxes share a cell.
    const float f = std::floor((p[a] - origin_[a]) * inverse_cell_[a]);
    cell[a] = f >= float(dims_[a] - 1) ? dims_[a] - 1 : (f > 0.0f ? int(f) : 0);
  }
  return cell;
}

bool BoxGrid::overlaps(uint32_t id, vec3 low, vec3 high) const {
  return !glm::any(glm::lessThan(high_[id], low)) && !glm::any(glm::greaterThan(low_[id], high));
}

void BoxGrid::overlapping(vec3 low, vec3 high, std::vector<uint32_t>& out) const {
  out.clear();
  if (cell_start_.empty() || glm::any(glm::greaterThan(low, high))) return;
  const glm::ivec3 a = cell_of(low), b = cell_of(high);
  for (int z = a.z; z <= b.z; ++z)
    for (int y = a.y; y <= b.y; ++y)
      for (int x = a.x; x <= b.x; ++x) {
        const size_t c = (size_t(z) * dims_.y + y) * dims_.x + x;
        for (uint32_t i = cell_start_[c]; i < cell_start_[c + 1]; ++i)
          if (overlaps(ids_[i], low, high)) out.push_back(ids_[i]);
      }
  for (uint32_t id : large_)
    if (overlaps(id, low, high)) out.push_back(id);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
}

}  // namespace lb
