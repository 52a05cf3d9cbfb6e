#pragma once
// The scene's area lights with one choice distribution shared by next-event estimation and
// light tracing: light j with probability in proportion to its power (sum of RGB watts), then
// a point uniformly over its area. Position independent, so the path tracer can evaluate the
// pdf of any point it hits (multiple importance sampling) in O(1).

#include <vector>

#include "bake/lights.h"

namespace lb::reference {

class LightSet {
 public:
  explicit LightSet(const Scene& scene);

  const std::vector<AreaLight>& lights() const { return lights_; }
  bool empty() const { return lights_.empty(); }
  // Index of the light chosen by u in [0,1) (requires !empty()).
  size_t choose(float u) const;
  float probability(size_t light) const { return probability_[light]; }
  // The light emitted by `mesh`, or -1.
  int light_of_mesh(uint32_t mesh) const;
  // Area density (1/m^2) with which choose() + AreaLight::sample() pick a point on `light`.
  float area_pdf(size_t light) const { return probability_[light] / lights_[light].area; }

 private:
  std::vector<AreaLight> lights_;
  std::vector<float> probability_;
  std::vector<float> cdf_;
  std::vector<int> mesh_light_;
};

}  // namespace lb::reference
