// `lightbake bake SCENE -o DIR`: run the bake passes and save their results.

#include <chrono>
#include <cstdio>
#include <string>

#include "app/commands.h"
#include "app/load.h"
#include "bake/accel.h"

namespace lb::app {

namespace {
struct BakeOptions {
  std::string scene_path;
  std::string output_dir = "bake";
};

void run_bake(const BakeOptions& options) {
  const Scene scene = load_or_exit(options.scene_path);
  const auto start = std::chrono::steady_clock::now();
  const Accel accel(scene);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("accel      %zu triangles in %.3f s\n", triangle_count(scene), seconds);
}
}  // namespace

void register_bake(CLI::App& app) {
  auto* cmd = app.add_subcommand("bake", "Bake illumination maps and vertex radiosity");
  auto options = std::make_shared<BakeOptions>();
  cmd->add_option("scene", options->scene_path, "Scene file (.toml, .gltf, .glb)")->required();
  cmd->add_option("-o,--output", options->output_dir, "Bake directory to write");
  cmd->callback([options] { run_bake(*options); });
}

}  // namespace lb::app
