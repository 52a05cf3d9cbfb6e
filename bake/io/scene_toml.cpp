#include "bake/io/scene_load.h"
namespace lb {
// Placeholder until the native loader lands.
LoadResult load_scene_toml(const std::string& path) { throw SceneError(path + ": TOML loader not built yet"); }
}  // namespace lb
