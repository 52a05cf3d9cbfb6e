#pragma once
// Reading an illumination map the way renderers do, for the pass 1 tests.

#include "bake/bake_result.h"

namespace lb::test {

// Bilinear read of the map at an atlas UV, as the GPU does it.
vec3 map_at_uv(const IlluminationMaps& maps, vec2 uv);

// The map at point p of planar mesh `mesh` (its triangle found by barycentrics); adds a test
// failure when p is on none of its triangles.
vec3 map_at(const IlluminationMaps& maps, const Scene& scene, size_t mesh, vec3 p);

}  // namespace lb::test
