#include "bake/io/scene_load.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

namespace lb {

LoadResult load_scene(const std::string& path, const SceneLoadOptions& options) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  if (extension == ".toml") return load_scene_toml(path);
  if (extension == ".gltf" || extension == ".glb") return load_scene_gltf(path, options);
  throw SceneError(path + ": unknown scene format '" + extension +
                   "' (expected .toml, .gltf or .glb)");
}

}  // namespace lb
