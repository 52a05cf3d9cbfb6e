#pragma once
// Output paths given on the command line: their folders are created before any long work
// starts, so a typo fails in a second instead of after a bake.

#include <string>

namespace lb::app {

// Creates the parent folder of `path` if needed; throws std::runtime_error naming the path.
void prepare_output_path(const std::string& path);

}  // namespace lb::app
