#pragma once
// The eye half of the reference (see reference.h for which paths it counts): unidirectional
// path tracing with next-event estimation at diffuse vertices, combined with the scattered
// ray's own hit by the power heuristic.

#include "bake/reference/shading.h"
#include "bake/sampling.h"

namespace lb::reference {

// Radiance W/(sr m^2) arriving along `ray` (from the lens), one sample.
vec3 trace_eye_path(const Context& context, const Ray& ray, Rng& rng, ReferenceRays& rays);

}  // namespace lb::reference
