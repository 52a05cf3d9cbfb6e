#include "app/load.h"

#include <cstdio>
#include <new>

#include "app/address_space.h"
#include "app/commands.h"
#include "bake/message_line.h"
#include "bake/pipeline/bake_settings.h"

namespace lb::app {

SceneLoadOptions& scene_load_options() {
  static SceneLoadOptions options;
  return options;
}

void add_scene_load_flags(CLI::App& app) {
  for (CLI::App* command : app.get_subcommands({}))
    if (command->get_option_no_throw("scene") != nullptr)  // the subcommands that load scenes
      command->add_flag("--allow-outside-uris", scene_load_options().allow_outside_uris,
                        "Let glTF buffer and image URIs point outside the scene's folder");
}

Scene load_or_exit(const std::string& path) {
  try {
    LoadResult result = load_scene(path, scene_load_options());
    for (const std::string& warning : result.warnings)
      print_message("warning", warning);
    BakeParams unused;  // the file's bake settings are checked now, before any work
    apply_scene_bake_settings(result.scene, unused);
    require_address_space_for(result.scene);
    return std::move(result.scene);
  } catch (const std::bad_alloc&) {
    print_message("error", path + ": " + out_of_memory_text(" while loading it"));
    throw ExitCode{1};
  } catch (const std::exception& e) {  // SceneError, and a bad [bake] key
    print_message("error", e.what());
    throw ExitCode{1};
  }
}

}  // namespace lb::app
