#include "bake/io/scene_load.h"

#include "bake/contact_conform.h"
#include "bake/input_file.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

namespace lb {

std::string first_line(const std::string& text) {
  std::string line = text.substr(0, text.find('\n'));
  while (!line.empty() && std::isspace(static_cast<unsigned char>(line.back()))) line.pop_back();
  return line;
}

LoadResult load_scene(const std::string& path, const SceneLoadOptions& options) {
  const std::string extension = lowercase_extension(path);
  LoadResult result;
  if (extension == ".toml")
    result = load_scene_toml(path);
  else if (extension == ".gltf" || extension == ".glb")
    result = load_scene_gltf(path, options);
  else
    throw SceneError(path + ": unknown scene format '" + extension +
                     "' (expected .toml, .gltf or .glb)");
  separate_dynamic_meshes(result.scene);
  recentre_far_scene(result.scene);
  conform_to_contacts(result.scene);
  return result;
}

}  // namespace lb
