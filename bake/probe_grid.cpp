#include "bake/probe_grid.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/constants.hpp>

namespace lb {

std::array<float, kShCoefficients> sh_basis(vec3 w) {
  const float x = w.x, y = w.y, z = w.z;
  return {0.282095f,
          0.488603f * y,
          0.488603f * z,
          0.488603f * x,
          1.092548f * x * y,
          1.092548f * y * z,
          0.315392f * (3.0f * z * z - 1.0f),
          1.092548f * x * z,
          0.546274f * (x * x - y * y)};
}

vec3 sh_irradiance(const ShL2& sh, vec3 n) {
  constexpr float pi = glm::pi<float>();
  constexpr float band[3] = {pi, 2.0f * pi / 3.0f, pi / 4.0f};
  constexpr int band_of[kShCoefficients] = {0, 1, 1, 1, 2, 2, 2, 2, 2};
  const std::array<float, kShCoefficients> y = sh_basis(n);
  vec3 e(0.0f);
  for (int i = 0; i < kShCoefficients; ++i) e += band[band_of[i]] * y[size_t(i)] * sh[size_t(i)];
  return glm::max(e, vec3(0.0f));
}

vec3 mesh_centre(const Mesh& mesh) {
  Bounds bounds;
  for (vec3 p : mesh.positions) bounds.extend(p);
  return bounds.empty() ? vec3(0.0f) : 0.5f * (bounds.min + bounds.max);
}

namespace {

bool sees(const Accel& accel, vec3 point, vec3 probe) {
  const vec3 d = probe - point;
  if (glm::dot(d, d) < 1e-12f) return true;
  const vec3 dir = glm::normalize(d);
  return !accel.occluded(segment_ray(point, dir, probe, dir));
}

}  // namespace

ProbeBlend blend_probes(const ProbeGrid& grid, const Accel& accel, vec3 point) {
  if (grid.empty()) return {};
  return blend_probes(grid, accel, point, [&](size_t index) {
    return grid.valid[index] ? &grid.sh[index] : nullptr;
  });
}

ProbeBlend blend_probes(const ProbeGrid& grid, const Accel& accel, vec3 point,
                        const std::function<const ShL2*(size_t index)>& probe) {
  ProbeBlend blend;
  if (grid.size() == 0) return blend;
  const glm::ivec3 last = grid.counts - 1;
  const vec3 f = (point - grid.origin) / grid.spacing;
  const glm::ivec3 base = glm::clamp(glm::ivec3(glm::floor(f)), glm::ivec3(0),
                                     glm::max(last - 1, glm::ivec3(0)));
  const vec3 t = glm::clamp(f - vec3(base), vec3(0.0f), vec3(1.0f));
  const int rings = std::max({grid.counts.x, grid.counts.y, grid.counts.z});
  for (int ring = 0; ring <= rings; ++ring) {
    glm::dvec3 sum[kShCoefficients];
    std::fill(std::begin(sum), std::end(sum), glm::dvec3(0.0));
    double total = 0.0;
    int used = 0;
    const glm::ivec3 lo = base - ring, hi = base + 1 + ring;
    for (int k = std::max(lo.z, 0); k <= std::min(hi.z, last.z); ++k)
      for (int j = std::max(lo.y, 0); j <= std::min(hi.y, last.y); ++j)
        for (int i = std::max(lo.x, 0); i <= std::min(hi.x, last.x); ++i) {
          const glm::ivec3 cell(i, j, k);
          // Ring r's probes are those of its block outside ring r - 1's (already refused).
          if (ring > 0 && glm::all(glm::greaterThan(cell, lo)) && glm::all(glm::lessThan(cell, hi)))
            continue;
          const vec3 position = grid.position(cell);
          double weight;
          if (ring == 0) {
            const vec3 d = vec3(cell - base);
            const vec3 w = d * t + (1.0f - d) * (1.0f - t);
            // A floor, so the renormalised blend still has a direction when the point sits
            // on a refused probe and the others' trilinear weights are all 0.
            weight = std::max(double(w.x) * w.y * w.z, 1e-4);
          } else {
            const vec3 d = (position - point) / grid.spacing;
            weight = 1.0 / (1e-6 + double(glm::dot(d, d)));
          }
          const ShL2* sh = probe(grid.index(cell));
          if (!sh || !sees(accel, point, position)) continue;
          for (int c = 0; c < kShCoefficients; ++c) sum[c] += weight * glm::dvec3((*sh)[size_t(c)]);
          total += weight;
          ++used;
        }
    if (used == 0) {
      if (glm::all(glm::lessThanEqual(lo, glm::ivec3(0))) && glm::all(glm::greaterThanEqual(hi, last)))
        break;  // the block covers the grid: nothing left to try
      continue;
    }
    for (int c = 0; c < kShCoefficients; ++c) blend.sh[size_t(c)] = vec3(sum[c] / total);
    blend.probes = used;
    blend.ring = ring;
    return blend;
  }
  return blend;
}

}  // namespace lb
