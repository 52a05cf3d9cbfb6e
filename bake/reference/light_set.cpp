#include "bake/reference/light_set.h"

#include <algorithm>

namespace lb::reference {

namespace {

// Normalises `weights` into probabilities and their cumulative sums (empty if they sum to 0).
void distribution(std::vector<float>& weights, std::vector<float>& cdf) {
  double total = 0.0;
  for (const float w : weights) total += double(w);
  cdf.clear();
  if (!(total > 0.0)) {
    std::fill(weights.begin(), weights.end(), 0.0f);
    return;
  }
  double running = 0.0;
  for (float& w : weights) {
    running += double(w);
    cdf.push_back(float(running / total));
    w = float(double(w) / total);
  }
  // Rounding must not leave u near 1 to a light of probability 0 at the end.
  for (size_t j = weights.size(); j-- > 0;) {
    cdf[j] = 1.0f;
    if (weights[j] > 0.0f) break;
  }
}

size_t invert(const std::vector<float>& cdf, float u) {
  const auto it = std::upper_bound(cdf.begin(), cdf.end(), u);
  return std::min(size_t(it - cdf.begin()), cdf.size() - 1);
}

}  // namespace

LightSet::LightSet(const Scene& scene) : sources_(scene), mesh_light_(scene.meshes.size(), -1) {
  for (size_t j = 0; j < sources_.size(); ++j) {
    const vec3 p = sources_.power(j);
    float power = std::max(float(double(p.x) + double(p.y) + double(p.z)), 0.0f);
    const LightKind kind = sources_.kind(j);
    if (kind == LightKind::area) {
      const AreaLight& light = sources_.area_light(j);
      if (!(light.area > 0.0f)) power = 0.0f;
      if (power > 0.0f) mesh_light_[size_t(light.mesh)] = int(j);
    }
    if (kind == LightKind::sky) sky_ = int(j);
    probability_.push_back(power);
    emitter_probability_.push_back(kind == LightKind::sky ? 0.0f : power);
  }
  distribution(probability_, cdf_);
  distribution(emitter_probability_, emitter_cdf_);
}

size_t LightSet::choose(float u) const {
  return invert(cdf_, u);
}

size_t LightSet::choose_emitter(float u) const {
  return invert(emitter_cdf_, u);
}

int LightSet::light_of_mesh(uint32_t mesh) const {
  return mesh < mesh_light_.size() ? mesh_light_[mesh] : -1;
}

}  // namespace lb::reference
