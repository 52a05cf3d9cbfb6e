#pragma once
// Registration of the subcommands; each lives in its own cmd_*.cpp.

#include <CLI/CLI.hpp>
#include <string>

namespace lb::app {

// Thrown by a subcommand that has already printed its message, to leave with a status.
struct ExitCode {
  int value = 1;
};

// Prints "lightbake: error: MESSAGE" and leaves with status 1.
[[noreturn]] void fail(const std::string& message);

void register_info(CLI::App& app);
void register_bake(CLI::App& app);
void register_render(CLI::App& app);
void register_reference(CLI::App& app);
void register_snapshot(CLI::App& app);
void register_view(CLI::App& app);
void register_compare(CLI::App& app);
void register_export(CLI::App& app);
void register_merge(CLI::App& app);

}  // namespace lb::app
