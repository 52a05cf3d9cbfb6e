#pragma once
// A bake directory on disk: manifest.json, illumination.exr and the radiosity meshes.
// Written to a temporary directory and renamed, so a crash never leaves half a bake.
#include <string>

#include "bake/bake_result.h"

namespace lb {

void save_bake(const std::string& directory, const Scene& scene, const BakeResult& bake);
BakeResult load_bake(const std::string& directory, const Scene& scene);  // throws on mismatch

}  // namespace lb
