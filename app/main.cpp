// lightbake: one executable, one subcommand per job. Each subcommand is a thin layer over
// the libraries in bake/ and viewer/; its options bind the same params structs the viewer uses.

#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <string>

#include "app/commands.h"
#include "app/load.h"

namespace lb::app {
void fail(const std::string& message) {
  std::fprintf(stderr, "lightbake: error: %s\n", message.c_str());
  throw ExitCode{1};
}
}  // namespace lb::app

int main(int argc, char** argv) {
  CLI::App app{"lightbake: an interactive lightmap baker after Shirley's three-pass method"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "lightbake 0.1");

  lb::app::register_info(app);
  lb::app::register_bake(app);
  lb::app::register_render(app);
  lb::app::register_reference(app);
  lb::app::register_snapshot(app);
  lb::app::register_view(app);
  lb::app::register_compare(app);
  lb::app::register_export(app);
  lb::app::register_merge(app);
  lb::app::add_scene_load_flags(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const lb::app::ExitCode& code) {
    return code.value;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "lightbake: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
