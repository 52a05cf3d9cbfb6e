#include "viewer/bake_settings_panel.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <string_view>
#include <utility>

namespace lb {

namespace {

// The key with spaces, shorter for the settings shown first so the panel stays narrow (the
// full key and the help are in the tooltip).
std::string label_of(const BakeSetting& setting) {
  static const std::pair<std::string_view, const char*> kShort[] = {
      {"rays_per_zone_side", "zone rays side"}, {"sky_directions_side", "sky dirs side"},
      {"soft_gather_rays", "gather rays"},      {"texel_size", "texel (m)"},
      {"patch_size", "patch (m)"},              {"ray_budget", "radiosity rays"}};
  for (const auto& [key, label] : kShort)
    if (key == setting.key) return label;
  std::string label = setting.key;
  std::replace(label.begin(), label.end(), '_', ' ');
  return label;
}

// One widget by the setting's kind; typed values are clamped and rounded the way set()
// requires, so the panel can never hold a value the bake would refuse.
bool setting_widget(const BakeSetting& setting, BakeParams& params) {
  const std::string label = label_of(setting);
  double value = setting.get(params);
  bool changed = false;
  if (setting.is_boolean()) {
    bool on = value != 0.0;
    changed = ImGui::Checkbox(label.c_str(), &on);
    value = on ? 1.0 : 0.0;
  } else {
    changed =
        ImGui::InputDouble(label.c_str(), &value, 0.0, 0.0, setting.is_integer() ? "%.0f" : "%.6g",
                           ImGuiInputTextFlags_EnterReturnsTrue);
    if (setting.is_integer()) value = std::round(value);
    value = std::clamp(value, setting.min, setting.max);
  }
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s: %s", setting.key, setting.help);
  if (changed) setting.set(params, value);
  return changed;
}

}  // namespace

bool bake_settings_panel(BakeParams& params) {
  bool changed = false;
  for (const BakeSetting& setting : bake_settings())
    if (setting.set_by_level || std::string_view(setting.key) == "seed")
      changed |= setting_widget(setting, params);
  if (ImGui::TreeNode("more settings")) {
    for (const BakeSetting& setting : bake_settings())
      if (!setting.set_by_level && std::string_view(setting.key) != "seed")
        changed |= setting_widget(setting, params);
    ImGui::TreePop();
  }
  return changed;
}

}  // namespace lb
