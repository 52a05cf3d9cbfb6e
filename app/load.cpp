#include "app/load.h"

#include <cstdio>

#include "app/commands.h"

namespace lb::app {

Scene load_or_exit(const std::string& path) {
  try {
    LoadResult result = load_scene(path);
    for (const std::string& warning : result.warnings)
      std::fprintf(stderr, "lightbake: warning: %s\n", warning.c_str());
    return std::move(result.scene);
  } catch (const SceneError& e) {
    std::fprintf(stderr, "lightbake: error: %s\n", e.what());
    throw ExitCode{1};
  }
}

}  // namespace lb::app
