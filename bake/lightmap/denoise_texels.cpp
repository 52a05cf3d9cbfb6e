#include "bake/lightmap/denoise_texels.h"

#include <algorithm>
#include <chrono>
#include <stdexcept>

#include "bake/lightmap/oidn.h"
#include "bake/lightmap/texel_footprint.h"

namespace lb {

namespace {

// Rings of gutter filled before denoising: OIDN's receptive field reaches far, but a few texels
// past the widest padding's middle keep chart edges from seeing black.
constexpr int kGutterRings = 16;

// Per texel, the index of its 4-connected group of covered texels (-1: uncovered).
std::vector<int> covered_groups(int width, int height, const std::vector<uint8_t>& covered,
                                size_t& groups) {
  std::vector<int> group(covered.size(), -1);
  std::vector<size_t> stack;
  groups = 0;
  for (size_t start = 0; start < covered.size(); ++start) {
    if (!covered[start] || group[start] >= 0) continue;
    const int id = int(groups++);
    group[start] = id;
    stack.assign(1, start);
    while (!stack.empty()) {
      const size_t k = stack.back();
      stack.pop_back();
      const int i = int(k % size_t(width)), j = int(k / size_t(width));
      const int next[4][2] = {{i - 1, j}, {i + 1, j}, {i, j - 1}, {i, j + 1}};
      for (const auto& [x, y] : next) {
        if (x < 0 || y < 0 || x >= width || y >= height) continue;
        const size_t n = size_t(y) * size_t(width) + size_t(x);
        if (covered[n] && group[n] < 0) {
          group[n] = id;
          stack.push_back(n);
        }
      }
    }
  }
  return group;
}

}  // namespace

std::vector<vec3> denoise_texels(int width, int height, const std::vector<uint8_t>& covered,
                                 const std::vector<vec3>& values, DenoiseStats* stats,
                                 const std::vector<vec3>* weight,
                                 const std::vector<uint8_t>* noisy) {
  const size_t texels = size_t(width) * size_t(height);
  if (values.size() != texels || covered.size() != texels ||
      (weight && weight->size() != texels) || (noisy && noisy->size() != texels))
    throw std::invalid_argument("denoise_texels: the images are not width x height");
  const auto start = std::chrono::steady_clock::now();
  if (noisy && std::find(noisy->begin(), noisy->end(), uint8_t(1)) == noisy->end()) {
    if (stats) *stats = DenoiseStats{};  // nothing noisy (no penumbra): OIDN is not run
    return values;
  }
  std::vector<vec3> filled = values;
  for (size_t k = 0; k < texels; ++k)
    if (!covered[k]) filled[k] = vec3(0.0f);
  dilate_texels(width, height, covered, filled, kGutterRings);
  const std::vector<vec3> denoised = oidn_denoise(width, height, filled);

  size_t groups = 0;
  const std::vector<int> group = covered_groups(width, height, covered, groups);
  std::vector<glm::dvec3> before(groups, glm::dvec3(0.0)), after(groups, glm::dvec3(0.0));
  const auto takes_output = [&](size_t k) { return group[k] >= 0 && (!noisy || (*noisy)[k]); };
  for (size_t k = 0; k < texels; ++k)
    if (takes_output(k)) {
      const glm::dvec3 w = weight ? glm::dvec3((*weight)[k]) : glm::dvec3(1.0);
      before[size_t(group[k])] += w * glm::dvec3(values[k]);
      after[size_t(group[k])] += w * glm::dvec3(denoised[k]);
    }
  std::vector<vec3> out = values;
  for (size_t k = 0; k < texels; ++k) {
    if (!takes_output(k)) continue;
    const size_t g = size_t(group[k]);
    for (int c = 0; c < 3; ++c)
      out[k][c] = after[g][c] > 0.0 ? float(double(denoised[k][c]) * before[g][c] / after[g][c])
                                    : values[k][c];
  }
  if (stats) {
    glm::dvec3 sum_before(0.0), sum_after(0.0);
    for (size_t g = 0; g < groups; ++g) sum_before += before[g], sum_after += after[g];
    const double total_before = sum_before.x + sum_before.y + sum_before.z;
    stats->texels = 0;
    for (size_t k = 0; k < texels; ++k) stats->texels += takes_output(k);
    stats->groups = groups;
    stats->energy_ratio =
        total_before > 0.0 ? (sum_after.x + sum_after.y + sum_after.z) / total_before : 1.0;
    stats->seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return out;
}

}  // namespace lb
