#pragma once
// Pass 1: illumination ray tracing (Shirley 1990, section 3.1; Arvo 1986). Feeler rays find
// the specular objects seen from each light, dense stratified rays follow light through
// mirrors, glass and glossy metal and splat its power onto the illumination maps of the
// diffuse surfaces they reach. Light that reaches a diffuse surface first is not recorded.

#include <cstdint>

#include "bake/accel.h"
#include "bake/bake_result.h"
#include "bake/progress.h"

namespace lb {

struct IlluminationParams {
  int feeler_zones = 6;            // feelers on a feeler_zones^2 grid over the hemisphere
  int rays_per_zone_side = 64;     // dense rays per traced zone: rays_per_zone_side^2
  // Ray origins: the light's centre gives sharp caustics and less noise; stratified points
  // over the whole light give soft caustics.
  bool origins_over_light = false;
  int max_depth = 16;              // specular bounces before a path is dropped
  float texel_size = 0.0f;         // map texel edge, metres; 0 = automatic
  uint64_t seed = 1;
};

IlluminationMaps trace_illumination(const Scene& scene, const Accel& accel,
                                    const IlluminationParams& params,
                                    const Progress& progress = {});

}  // namespace lb
