#pragma once
// Which of many axis-aligned boxes overlap a query box, without testing them all (issue 16:
// the contact cuts scanned every triangle of the scene for every receiving mesh, and every
// cutter for every receiving triangle, which grew with the square of the triangles).
//
// A uniform grid over the boxes' bounds, about one cell per box, shaped like the bounds; each
// box is listed in every cell it touches, and boxes that touch more than kMaxCellsPerBox cells
// (a whole floor) are kept aside and always tested. Box and query map to cells through the
// same monotone function, so every overlapping box is found; the ids come back ascending, so
// callers that depend on the order (plane ids) see the order of a plain scan.

#include <cstdint>
#include <vector>

#include "bake/scene.h"

namespace lb {

class BoxGrid {
 public:
  // Boxes as (low, high) corners; an empty box (low > high) is never returned.
  BoxGrid(std::vector<vec3> low, std::vector<vec3> high);

  // Appends to `out` (cleared first) the ids of the boxes overlapping [low, high], the bounds
  // included, ascending.
  void overlapping(vec3 low, vec3 high, std::vector<uint32_t>& out) const;

  static constexpr int64_t kMaxCellsPerBox = 64;

 private:
  glm::ivec3 cell_of(vec3 p) const;
  bool overlaps(uint32_t id, vec3 low, vec3 high) const;

  std::vector<vec3> low_, high_;
  vec3 origin_{0.0f}, inverse_cell_{0.0f};
  glm::ivec3 dims_{1};
  std::vector<uint32_t> cell_start_;  // CSR: ids of cell c at ids_[cell_start_[c] ..]
  std::vector<uint32_t> ids_;
  std::vector<uint32_t> large_;  // boxes over more than kMaxCellsPerBox cells, ascending
};

}  // namespace lb
