#include "viewer/light_group_mix.h"

#include <imgui.h>

#include <algorithm>

#include "bake/light_groups.h"

namespace lb {

void LightGroupMix::reset(const Scene& scene, const BakeResult* bake, const std::string& given) {
  groups_ = bake ? bake->light_groups : std::vector<std::string>{};
  weights_.clear();
  if (groups_.empty()) return;
  weights_ = resolve_group_weights(groups_, given.empty() ? std::vector<LightGroupWeight>{} : parse_group_weights(given), scene.source_path);
}

bool LightGroupMix::panel() {
  if (!active() || !ImGui::CollapsingHeader("Light groups", ImGuiTreeNodeFlags_DefaultOpen))
    return false;
  bool changed = false;
  for (size_t g = 0; g < groups_.size(); ++g)
    changed |= ImGui::SliderFloat(groups_[g].c_str(), &weights_[g], 0.0f, 4.0f);
  return changed;
}

void LightGroupMix::apply(const Scene& scene, const BakeResult& bake) {
  std::vector<float> lit = weights_;
  for (float& w : lit) w = std::max(w, 1e-6f);
  scene_ = scale_light_groups(scene, lit);
  bake_ = blend_light_groups(bake, weights_);
}

}  // namespace lb
