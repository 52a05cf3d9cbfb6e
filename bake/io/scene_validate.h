#pragma once
// validate_scene (declared in scene_load.h) with better places for loaders that know them.

#include <string>
#include <vector>

#include "bake/io/scene_load.h"

namespace lb {

// As validate_scene, but messages about mesh i start with `mesh_places[i]` (e.g.
// "scene.toml:12:1: objects[3]") instead of the scene file alone. `mesh_places` is either
// empty or as long as scene.meshes. Without `whole_scene` (an included file) a scene that emits
// no light is not warned about: the file including it may light it.
void validate_scene(Scene& scene, std::vector<std::string>& warnings,
                    const std::vector<std::string>& mesh_places, bool whole_scene = true);

}  // namespace lb
