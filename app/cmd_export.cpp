// `lightbake export SCENE [BAKE_DIR] -o out.glb|out.gltf`: the bake as a lightmapped glTF 2.0
// for engines and the web (bake/export/gltf_export.h, docs/export.md). Bakes first with default
// settings when no BAKE_DIR is given; Ctrl-C during the bake or the lightmap leaves nothing
// written. `--shard i/n -o PART.texshard` bakes one shard of the direct light's texels
// (bake/export/export_shard.h; the command part app/export_shard.h).

#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "app/bake_options.h"
#include "app/cli_parse.h"
#include "app/commands.h"
#include "app/console_progress.h"
#include "app/export_options.h"
#include "app/export_shard.h"
#include "app/group_weights_option.h"
#include "app/load.h"
#include "app/output_path.h"
#include "app/thread_option.h"
#include "bake/export/export_shard.h"
#include "bake/export/gltf_export.h"
#include "bake/pipeline/bake.h"
#include "bake/pipeline/bake_io.h"
#include "bake/probes/dynamic_light.h"

namespace lb::app {

namespace {

struct ExportOptions {
  std::string scene_path;
  std::string bake_dir;
  std::string output;
  ExportSettings settings;  // what the file holds (export_options.h)
  std::string group_weights;  // one fixed mix of the light groups
  BakeCommandLine bake;  // the settings of the bake made when no BAKE_DIR
  bool quiet = false;
  bool force = false;
  std::string shard;  // "i/n": bake one shard of the direct light's texels (merge joins them)
};

void run_export(const ExportOptions& options) {
  const ExportSettings& settings = options.settings;
  if (!options.shard.empty() && settings.ktx2)
    fail("--ktx2: not with --shard (the merge writes no KTX2)");
  GltfExportOptions gltf;
  try {
    // A shard bakes the direct term only: the merge denoises (and needs the library).
    ExportSettings checked = settings;
    if (!options.shard.empty()) checked.denoise = false;
    gltf = resolve_export_settings(checked);
  } catch (const std::invalid_argument& e) {
    fail(e.what());
  }
  if (!options.shard.empty()) {
    const ShardOption shard = parse_shard(options.shard, kMaxExportShards);
    if (settings.contents != "all")
      fail("--shard: only the direct light of --contents all is sharded (the rest is a copy)");
    ExportShardOptions part;
    part.scene_path = options.scene_path;
    part.bake_dir = options.bake_dir;
    part.output = options.output;
    part.lightmap_format = settings.format;
    part.lightmap_encoding = settings.encoding;
    part.direct_side = settings.direct_side;
    part.denoise = settings.denoise;          // the merge runs it, on the joined term
    part.shadow_side = settings.shadow_side;  // recorded: one set, one plan of the rays
    part.directional = settings.directional;  // the direct term's L1 too; merge makes the rest
    part.directional_share = settings.directional_share;
    part.index = shard.index;
    part.count = shard.count;
    part.force = options.force;
    part.quiet = options.quiet;
    return write_export_shard(part);
  }
  const std::string extension = std::filesystem::path(options.output).extension().string();
  if (extension != ".glb" && extension != ".gltf")
    fail(options.output + ": output must be .glb or .gltf");
  // A missing folder is a typo more often than a wish (issue 12): refused, not created.
  const std::filesystem::path folder = std::filesystem::path(options.output).parent_path();
  if (!folder.empty() && !std::filesystem::is_directory(folder))
    fail(options.output + ": the folder '" + folder.string() + "' does not exist");
  // Every file is checked before any bake, so a refusal comes in a second.
  for (const std::string& path : export_paths(options.output, gltf))
    prepare_output_file(path, options.force);

  Scene scene = load_or_exit(options.scene_path);
  const std::vector<float> group_weights = scene_group_weights(scene, options.group_weights);
  const ConsoleProgress console(options.quiet);  // Ctrl-C cancels: nothing is written
  BakeResult bake;
  // The map is the atlas's size: its files' space is checked before the bake's first ray.
  const auto require_space = [&](int atlas_width, int atlas_height) {
    require_free_space(options.output,
                       export_files_bytes(scene, atlas_width, atlas_height, options.output, gltf));
  };
  if (options.bake_dir.empty()) {
    BakeCallbacks callbacks;
    callbacks.on_atlas = require_space;
    BakeCommandLine line = options.bake;  // --directional asks the bake for its band too
    if (settings.directional) line.directional = true;
    bake = bake_scene(scene, resolve_bake_params(scene, line), console.progress(),
                      callbacks);
  } else {
    bake = load_bake(options.bake_dir, scene);
    require_space(bake.illumination.width, bake.illumination.height);
  }
  apply_group_weights(group_weights, scene, &bake);
  // Moving objects: the probe grid and each object's light (docs/light-probes.md).
  ExportProbes probes;
  if (!scene.dynamic_meshes.empty()) {
    probes = bake_export_probes(scene, bake, {}, console.progress());
    gltf.light_probes = &probes.grid;
    gltf.dynamic_sh = &probes.blends;
  }
  const GltfExportInfo info = export_gltf(options.output, scene, bake, gltf, console.progress());
  if (options.quiet) return;
  std::printf("export     %zu meshes (%zu with a lightmap), %zu triangles, %zu vertices\n",
              info.meshes, info.lightmapped_meshes, info.triangles, info.vertices);
  if (info.map_width > 0)
    std::printf(
        "lightmap   %dx%d at %.4g texels/m, contents %s, 8-bit %s x %.6g W/(sr m^2) in the "
        "glTF%s, %.3f s\n",
        info.map_width, info.map_height, double(info.texel_density), to_string(info.contents),
        gltf.encoding == LightmapEncoding::rgbm ? "RGBM" : "sRGB", double(info.map_scale),
        info.contents == LightmapContents::all
            ? (", " + std::to_string(info.shadow_rays) + " shadow rays").c_str()
            : "",
        info.lightmap_seconds);
  if (info.denoised)
    std::printf("denoise    direct term's %zu texels, Open Image Denoise (energy %.5f before "
                "rescaling %zu chart groups), %.3f s\n",
                info.denoise.texels, info.denoise.energy_ratio, info.denoise.groups,
                info.denoise.seconds);
  if (info.ktx2_bytes > 0)
    std::printf("ktx2       the map in %zu bytes (UASTC, %s; the PNG %zu bytes kept as "
                "fallback)\n",
                info.ktx2_bytes,
                info.ktx2_mipmaps ? "with its mip chain" : "level 0 only: sides not multiples of 4",
                info.png_bytes);
  if (info.directional)
    std::printf("directional L1 band: 3 more 8-bit maps (%s, %s), %.3f s of its own\n",
                "LIGHTBAKE_lightmap_directional",
                gltf.directional_share ? "x RGBA with the share s, 13/3 of the map's bytes"
                                       : "RGB, 4x the map's bytes",
                info.directional_seconds);
  if (info.group_layers > 0)
    std::printf("groups     %zu light groups' maps as layers (%s)\n", info.group_layers,
                "LIGHTBAKE_lightmap_groups");
  for (const std::string& file : info.files) std::printf("wrote      %s\n", file.c_str());
}

}  // namespace

void register_export(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "export", "Export a bake as lightmapped glTF 2.0 (.glb/.gltf) for engines and the web");
  auto options = std::make_shared<ExportOptions>();
  cmd->add_option("scene", options->scene_path, "Scene file (.toml, .gltf, .glb)")->required();
  cmd->add_option("bake_dir", options->bake_dir, "Bake directory (omitted: bake first)");
  cmd->add_option("-o,--output", options->output,
                  "glTF to write (.glb or .gltf); with --shard, PART.texshard")
      ->required();
  add_export_options(*cmd, options->settings);
  cmd->add_flag("-q,--quiet", options->quiet, "No progress output");
  cmd->add_flag("--force", options->force,
                "Replace the output or its lightmap files even if lightbake did not write them");
  cmd->add_option("--shard", options->shard,
                  "INDEX/COUNT: with --contents all and BAKE_DIR, bake only this shard's rows of "
                  "the direct light (with --directional its L1 too), as .texshard; `lightbake "
                  "merge` writes the glTF, bit for bit (docs/farm.md)");
  add_bake_options(*cmd, options->bake, kBakeFirstGroup, /*with_seed=*/true);
  add_group_weights_option(*cmd, options->group_weights);
  add_threads_option(*cmd);
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
