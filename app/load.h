#pragma once
// Loading a scene for a subcommand: warnings to stderr, errors as one line and a status.

#include <CLI/CLI.hpp>
#include <string>

#include "bake/io/scene_load.h"

namespace lb::app {

// The loader options the command line chose (`--allow-outside-uris`), shared by every
// subcommand that loads a scene.
SceneLoadOptions& scene_load_options();

// Adds the loader flags to each subcommand of `app` (call after registering them).
void add_scene_load_flags(CLI::App& app);

// Loads and validates with scene_load_options(), prints each warning as
// "lightbake: warning: ...". On a SceneError prints "lightbake: error: ..." and throws
// ExitCode{1}.
Scene load_or_exit(const std::string& path);

}  // namespace lb::app
