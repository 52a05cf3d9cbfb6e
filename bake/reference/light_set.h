#pragma once
// Every light of the scene (bake/light_sources.h: area lights, lamps, the sky) with the choice
// distributions the two tracers share: light j with probability in proportion to its power
// (sum of RGB watts; lights at infinity by LightSources::power, the power crossing the scene's
// bounding disk). Next-event estimation chooses among every light; light tracing among every
// light but the sky (the path tracer finds the sky's caustics by itself, docs/reference.md).
// Area lights then take a point uniformly over their area. Position independent, so the path
// tracer can evaluate the pdf of any point it hits (multiple importance sampling) in O(1).
// Light indices are LightSources'.

#include <vector>

#include "bake/light_sources.h"

namespace lb::reference {

class LightSet {
 public:
  explicit LightSet(const Scene& scene);

  const LightSources& sources() const { return sources_; }
  // Whether next-event estimation has a light to choose (some light has power).
  bool empty() const { return cdf_.empty(); }
  // Index of the light chosen by u in [0,1) (requires !empty()).
  size_t choose(float u) const;
  float probability(size_t light) const { return probability_[light]; }
  // Light tracing's choice: the same without the sky (requires !emitters_empty()).
  bool emitters_empty() const { return emitter_cdf_.empty(); }
  size_t choose_emitter(float u) const;
  float emitter_probability(size_t light) const { return emitter_probability_[light]; }
  // The area light emitted by `mesh`, or -1.
  int light_of_mesh(uint32_t mesh) const;
  // Area density (1/m^2) with which choose() + AreaLight::sample() pick a point on area light
  // `light`.
  float area_pdf(size_t light) const {
    return probability_[light] / sources_.area_light(light).area;
  }
  // The sky's index, or -1.
  int sky() const { return sky_; }

 private:
  LightSources sources_;
  std::vector<float> probability_, cdf_;
  std::vector<float> emitter_probability_, emitter_cdf_;
  std::vector<int> mesh_light_;
  int sky_ = -1;
};

}  // namespace lb::reference
