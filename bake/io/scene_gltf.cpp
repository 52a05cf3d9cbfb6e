#include "bake/io/scene_load.h"
namespace lb {
// Placeholder until the glTF loader lands.
LoadResult load_scene_gltf(const std::string& path) { throw SceneError(path + ": glTF loader not built yet"); }
}  // namespace lb
