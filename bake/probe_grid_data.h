#pragma once
// The light-probe grid as plain data (issue 38), apart from its blend (bake/probe_grid.h) so
// that a Scene can hold the grid an export wrote (Scene::probe_grid). The convention of the
// coefficients: bake/probe_grid.h.

#include <array>
#include <cstddef>
#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

namespace lb {

using glm::vec3;

constexpr int kShCoefficients = 9;  // L2: bands 0, 1, 2
using ShL2 = std::array<vec3, kShCoefficients>;

struct ProbeGrid {
  vec3 origin{0.0f};       // the position of probe (0, 0, 0), metres
  vec3 spacing{1.0f};      // metres between neighbours along x, y, z
  glm::ivec3 counts{0};    // probes along x, y, z
  std::vector<uint8_t> valid;  // per probe: 0 inside geometry (excluded from every blend)
  std::vector<ShL2> sh;        // per probe, the convention above
  // Probe (i, j, k) is entry i + counts.x (j + counts.y k).
  size_t index(glm::ivec3 cell) const {
    return size_t(cell.x) + size_t(counts.x) * (size_t(cell.y) + size_t(counts.y) * size_t(cell.z));
  }
  glm::ivec3 cell(size_t index) const {
    const size_t x = size_t(counts.x), xy = x * size_t(counts.y);
    return {int(index % x), int(index / x % size_t(counts.y)), int(index / xy)};
  }
  vec3 position(glm::ivec3 cell) const { return origin + vec3(cell) * spacing; }
  size_t size() const { return size_t(counts.x) * size_t(counts.y) * size_t(counts.z); }
  bool empty() const { return sh.empty(); }
};

}  // namespace lb
