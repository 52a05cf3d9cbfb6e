#pragma once
// Loading a scene for a subcommand: warnings to stderr, errors as one line and a status.

#include <string>

#include "bake/io/scene_load.h"

namespace lb::app {

// Loads and validates, prints each warning as "lightbake: warning: ...". On a SceneError
// prints "lightbake: error: ..." and throws ExitCode{1}.
Scene load_or_exit(const std::string& path);

}  // namespace lb::app
