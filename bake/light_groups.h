#pragma once
// Light groups (issue 39): lights that a game switches together (day, night, a lamp, an alarm).
// An emitting material, a lamp and the sky may name a group (`group = "NAME"` in TOML,
// `extras.lightbake_group` in glTF); lights without one form the group `default`. Light
// transport is linear in the emitted power and no pass's rays depend on how bright a light is,
// so one bake carries every group's light along the same rays (BakeResult::light_groups and
// the `group_*` arrays of bake_result.h), and at view time
//     light = sum over groups g of w_g * light_g        (every stored term, and direct light)
// with the weights given by `--group-weights NAME=W,...` (1 for a group not named; 0 turns a
// group off). A scene whose lights all lie in `default` has no groups: its bake is the same,
// bit for bit, as before groups existed.

#include <string>
#include <vector>

#include "bake/bake_result.h"
#include "bake/light_sources.h"
#include "bake/scene.h"

namespace lb {

inline constexpr const char* kDefaultLightGroup = "default";

// The group of a light as written ("" = default).
inline const std::string& group_name_or_default(const std::string& group) {
  static const std::string fallback = kDefaultLightGroup;
  return group.empty() ? fallback : group;
}

// The scene's groups in order of first appearance (emitting meshes in mesh order, then lamps,
// then the sky), `default` among them where some light names none; empty when no light names
// a group other than `default` (the scene uses no groups).
std::vector<std::string> light_group_names(const Scene& scene);

// Per light of `sources` (LightSources order), its index into `names`; empty when `names` is.
std::vector<int> light_group_of_sources(const Scene& scene, const LightSources& sources,
                                        const std::vector<std::string>& names);

// Per group of light_group_names (or the one group `default` when it is empty), the power its
// lights emit, W per channel (LightSources::power: lights at infinity count what crosses the
// scene's bounding disk).
struct LightGroupPower {
  std::string name;
  vec3 power{0.0f};
  size_t lights = 0;
};
std::vector<LightGroupPower> light_group_powers(const Scene& scene);

// `--group-weights day=0.3,night=2`: names and weights (finite, >= 0). Throws
// std::invalid_argument quoting the bad entry.
struct LightGroupWeight {
  std::string name;
  float weight = 1.0f;
};
std::vector<LightGroupWeight> parse_group_weights(const std::string& text);

// The weight of each of `groups` (1 where not given). Throws std::invalid_argument naming the
// group and `scene_path` when a given name is not one of them (`default` is always accepted:
// without groups it weighs the whole light).
std::vector<float> resolve_group_weights(const std::vector<std::string>& groups,
                                         const std::vector<LightGroupWeight>& given,
                                         const std::string& scene_path);

// The scene with every light's emission times its group's weight (direct light at view time);
// `weights` as resolve_group_weights returns them for light_group_names(scene) (one weight,
// for `default`, when the scene has no groups).
Scene scale_light_groups(const Scene& scene, const std::vector<float>& weights);

// The bake's light as sum_g w_g light_g in every stored term (maps, vertex radiosity, soft
// texels), with the per-group arrays dropped: renderers and the export read the result as any
// bake. Without groups, one weight scales the whole light. Throws std::invalid_argument when
// the weights do not match the bake's groups.
BakeResult blend_light_groups(const BakeResult& bake, const std::vector<float>& weights);

}  // namespace lb
