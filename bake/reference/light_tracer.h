#pragma once
// The light half of the reference: the paths L S+ D E (see reference.h). Particles leave the
// lights but the sky (light by power; area lights: point uniform over the area, direction
// cosine-weighted; lamps: LightSources::emit), follow the specular chain, and at the first
// diffuse vertex are connected to a uniform point on the lens. A delta lamp's particle that
// began with a specular vertex goes on past it (diffuse bounces cosine-weighted), connected
// at every diffuse vertex: L S+ D (D|S)* D E from such lamps is light tracing's too.

#include <cstdint>
#include <vector>

#include "bake/reference/shading.h"
#include "bake/sampling.h"

namespace lb::reference {

struct Splat {
  uint32_t pixel = 0;  // y * width + x
  vec3 value{0.0f};    // W/(sr m^2), already divided by the pass's light path count
};

// Traces `count` light paths from `rng`, appending their splats. `paths_in_pass` is the number
// of light paths of the whole pass (each splat is one path's share of the pass's estimate).
void trace_light_paths(const Context& context, size_t count, double paths_in_pass, Rng& rng,
                       std::vector<Splat>& splats, ReferenceRays& rays);

}  // namespace lb::reference
