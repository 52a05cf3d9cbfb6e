#include "bake/reference/light_set.h"

#include <algorithm>

namespace lb::reference {

LightSet::LightSet(const Scene& scene) : mesh_light_(scene.meshes.size(), -1) {
  double total = 0.0;
  for (AreaLight& light : collect_lights(scene)) {
    const double power = double(light.power.x) + double(light.power.y) + double(light.power.z);
    if (!(light.area > 0.0f) || !(power > 0.0)) continue;
    mesh_light_[size_t(light.mesh)] = int(lights_.size());
    probability_.push_back(float(power));
    lights_.push_back(std::move(light));
    total += power;
  }
  double running = 0.0;
  for (float& p : probability_) {
    running += p;
    cdf_.push_back(float(running / total));
    p = float(p / total);
  }
  if (!cdf_.empty()) cdf_.back() = 1.0f;
}

size_t LightSet::choose(float u) const {
  const auto it = std::upper_bound(cdf_.begin(), cdf_.end(), u);
  return std::min(size_t(it - cdf_.begin()), lights_.size() - 1);
}

int LightSet::light_of_mesh(uint32_t mesh) const {
  return mesh < mesh_light_.size() ? mesh_light_[mesh] : -1;
}

}  // namespace lb::reference
