#pragma once
// The light groups in the viewer (bake/light_groups.h): a slider per group in the panel, the
// bake's light blended and the scene's lights scaled with the weights, live: a slider moved is
// one blend on the CPU and one upload of the baked terms and light colours (no rebake, no
// shadow pass); a frame costs what it cost before.

#include <string>
#include <vector>

#include "bake/bake_result.h"
#include "bake/scene.h"

namespace lb {

class LightGroupMix {
 public:
  // The groups of `bake` (none: null or a bake without groups), weighed as `given` says
  // (`--group-weights` text, 1 for a group not named). Throws std::invalid_argument naming an
  // unknown group and the scene.
  void reset(const Scene& scene, const BakeResult* bake, const std::string& given);
  // Whether the shown bake has groups (the sliders, and scene()/bake() to draw).
  bool active() const { return !groups_.empty(); }
  // Draws a slider per group in the current ImGui window; true when one moved.
  bool panel();
  // Weighs `scene`'s lights and `bake`'s light; then scene() and bake() hold them. A weight 0
  // leaves the lights at 1e-6 of their emission in the scene drawn, so their shapes (and
  // shadow cubes) stay; the baked light is blended with the weights as they are.
  void apply(const Scene& scene, const BakeResult& bake);
  const Scene& scene() const { return scene_; }
  const BakeResult& bake() const { return bake_; }

 private:
  std::vector<std::string> groups_;
  std::vector<float> weights_;
  Scene scene_;
  BakeResult bake_;
};

}  // namespace lb
