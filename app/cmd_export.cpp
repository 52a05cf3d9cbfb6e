// `lightbake export SCENE [BAKE_DIR] -o out.glb|out.gltf`: the bake as a lightmapped glTF 2.0
// for engines and the web (bake/io/gltf_export.h, docs/export.md). Bakes first with default
// settings when no BAKE_DIR is given; Ctrl-C during that bake leaves nothing written.

#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "app/commands.h"
#include "app/console_progress.h"
#include "app/load.h"
#include "app/output_path.h"
#include "bake/io/gltf_export.h"
#include "bake/pipeline/bake.h"
#include "bake/pipeline/bake_io.h"

namespace lb::app {

namespace {

struct ExportOptions {
  std::string scene_path;
  std::string bake_dir;
  std::string output;
  uint64_t seed = 1;
  bool quiet = false;
  bool force = false;
};

void run_export(const ExportOptions& options) {
  const std::string extension = std::filesystem::path(options.output).extension().string();
  if (extension != ".glb" && extension != ".gltf")
    fail(options.output + ": output must be .glb or .gltf");
  // Both files are checked before any bake, so a refusal comes in a second.
  prepare_output_file(options.output, options.force);
  prepare_output_file(lightmap_exr_path(options.output), options.force);

  const Scene scene = load_or_exit(options.scene_path);
  const ConsoleProgress console(options.quiet);  // Ctrl-C cancels: nothing is written
  BakeResult bake;
  if (options.bake_dir.empty()) {
    BakeParams params;
    params.seed = options.seed;
    bake = bake_scene(scene, params, console.progress());
  } else {
    bake = load_bake(options.bake_dir, scene);
  }
  const GltfExportInfo info = export_gltf(options.output, scene, bake);
  if (options.quiet) return;
  std::printf(
      "export     %zu meshes (%zu with vertex radiosity, %zu with a lightmap), %zu "
      "triangles, %zu vertices\n",
      info.meshes, info.radiosity_meshes, info.lightmapped_meshes, info.triangles, info.vertices);
  if (info.map_width > 0)
    std::printf("lightmap   %dx%d, 8-bit sRGB x %.6g W/(sr m^2) in the glTF; half float in %s\n",
                info.map_width, info.map_height, double(info.map_scale),
                lightmap_exr_path(options.output).c_str());
  std::printf("wrote      %s (%zu bytes)\n", options.output.c_str(), info.bytes);
}

}  // namespace

void register_export(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "export", "Export a bake as lightmapped glTF 2.0 (.glb/.gltf) for engines and the web");
  auto options = std::make_shared<ExportOptions>();
  cmd->add_option("scene", options->scene_path, "Scene file (.toml, .gltf, .glb)")->required();
  cmd->add_option("bake_dir", options->bake_dir, "Bake directory (omitted: bake first)");
  cmd->add_option("-o,--output", options->output, "glTF to write (.glb or .gltf)")->required();
  cmd->add_option("--seed", options->seed, "Random seed of the bake made when no BAKE_DIR");
  cmd->add_flag("-q,--quiet", options->quiet, "No progress output");
  cmd->add_flag("--force", options->force,
                "Replace the output or its .lightmap.exr even if lightbake did not write them");
  cmd->callback([options] {
    try {
      run_export(*options);
    } catch (const Cancelled&) {
      std::fprintf(stderr, "lightbake: export cancelled; nothing written\n");
      throw ExitCode{130};
    }
  });
}

}  // namespace lb::app
