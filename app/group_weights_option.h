#pragma once
// `--group-weights NAME=W,...` (snapshot, render, export): the bake's light groups blended with
// these weights, and direct light scaled with them (bake/light_groups.h).

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "bake/bake_result.h"
#include "bake/scene.h"

namespace lb::app {

void add_group_weights_option(CLI::App& cmd, std::string& text);

// The weight of each of the scene's groups (1 where not given), checked before any bake: an
// unknown name is one line naming the group and the scene. Empty when `text` is.
std::vector<float> scene_group_weights(const Scene& scene, const std::string& text);

// Applies `weights` (scene_group_weights) to the scene's lights and the bake's light (none:
// null); nothing when they are empty. Call after the bake is made or loaded (its checks see
// the file's scene).
void apply_group_weights(const std::vector<float>& weights, Scene& scene, BakeResult* bake);

}  // namespace lb::app
