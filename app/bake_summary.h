#pragma once
// The lines `lightbake bake` (and `lightbake merge` of pass-1 shards) print after a bake.

#include <string>

#include "bake/bake_result.h"

namespace lb::app {

// Both passes' rays, seconds and energy, the peak memory, and where the bake was saved.
void print_bake_summary(const Scene& scene, const BakeResult& bake, const std::string& directory);

}  // namespace lb::app
