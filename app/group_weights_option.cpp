#include "app/group_weights_option.h"

#include "bake/light_groups.h"

namespace lb::app {

void add_group_weights_option(CLI::App& cmd, std::string& text) {
  cmd.add_option("--group-weights", text,
                 "Light groups blended with these weights, e.g. day=0.3,night=2 (1 for a group "
                 "not named, 0 turns one off); direct light scales with them");
}

std::vector<float> scene_group_weights(const Scene& scene, const std::string& text) {
  if (text.empty()) return {};
  return resolve_group_weights(light_group_names(scene), parse_group_weights(text),
                               scene.source_path);
}

void apply_group_weights(const std::vector<float>& weights, Scene& scene, BakeResult* bake) {
  if (weights.empty()) return;
  scene = scale_light_groups(scene, weights);
  if (bake) *bake = blend_light_groups(*bake, weights);
}

}  // namespace lb::app
