#pragma once
// Old option spellings kept working after a rename (docs/command-line.md, "One name per concept").

#include <CLI/CLI.hpp>
#include <string>

namespace lb::app {

// Adds OLD_NAME as a hidden alias of `current` (a string option already on `cmd`): it stores
// into the same `target` and prints one line on stderr naming the new spelling. Giving both
// is an error.
CLI::Option* add_deprecated_alias(CLI::App& cmd, CLI::Option* current, const std::string& old_name,
                                  std::string& target);

}  // namespace lb::app
