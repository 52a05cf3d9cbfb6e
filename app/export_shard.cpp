#include "app/export_shard.h"

#include <chrono>
#include <cstdio>
#include <filesystem>

#include "app/commands.h"
#include "app/console_progress.h"
#include "app/load.h"
#include "app/output_path.h"
#include "bake/export/export_shard.h"
#include "bake/export/gltf_export.h"
#include "bake/lightmap/directional_lightmap.h"
#include "bake/lightmap/lightmap.h"
#include "bake/lightmap/oidn.h"
#include "bake/pipeline/bake_io.h"

namespace lb::app {

void write_export_shard(const ExportShardOptions& options) {
  if (options.bake_dir.empty())
    fail("export --shard: give the bake directory (bake once, then every shard reads it)");
  shards::check_shard_extension(options.output, kExportShard);
  try {
    parse_lightmap_format(options.lightmap_format);
    parse_lightmap_encoding(options.lightmap_encoding);
  } catch (const std::invalid_argument& e) {
    fail(e.what());
  }
  const std::string report_path = shards::shard_report_path(options.output);
  prepare_output_file(options.output, options.force);
  prepare_output_file(report_path, options.force);

  const auto start = std::chrono::steady_clock::now();
  const Scene scene = load_or_exit(options.scene_path);
  const BakeResult bake = load_bake(options.bake_dir, scene);
  LightmapParams params;  // as export_gltf sets them
  params.contents = LightmapContents::all;
  params.direct_side = options.direct_side;
  params.shadow_side = options.shadow_side;
  params.seed = bake.seed;
  params.shard = options.index;
  params.shard_count = options.count;
  const ConsoleProgress console(options.quiet);  // Ctrl-C cancels: nothing is written
  const ExportShardSource source{options.scene_path,      options.bake_dir,
                                 scene_hash(scene),       bake_hash(bake),
                                 options.lightmap_format, options.lightmap_encoding,
                                 options.direct_side,     options.denoise,
                                 options.directional,     options.directional_share,
                                 options.shadow_side};
  const auto seconds_since_start = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  TexelRows rows;
  int width = 0, height = 0;
  uint64_t shadow_rays = 0;
  if (options.directional) {  // the direct term with its L1 (directional_lightmap.h)
    const DirectBand band = bake_direct_band(scene, bake, params, console.progress());
    lb::write_export_shard(options.output, source, band, options.index, options.count,
                           seconds_since_start());
    rows = band.rows, width = band.width, height = band.height, shadow_rays = band.shadow_rays;
  } else {
    const Lightmap lightmap = bake_lightmap(scene, bake, params, console.progress());
    lb::write_export_shard(options.output, source, lightmap, options.index, options.count,
                           seconds_since_start());
    rows = lightmap.direct_rows, width = lightmap.width, height = lightmap.height;
    shadow_rays = lightmap.shadow_rays;
  }
  if (options.quiet) return;
  std::printf(
      "export     shard %d/%d: direct light%s of lightmap rows %d-%d of %d (%dx%d), %llu "
      "shadow rays, %.2f s\n",
      options.index, options.count, options.directional ? " and its L1" : "", rows.begin,
      rows.end - 1, height, width, height, (unsigned long long)shadow_rays,
      seconds_since_start());
  std::printf("wrote      %s, %s\n", options.output.c_str(), report_path.c_str());
}

void merge_export_shards(const ExportMergeOptions& options) {
  ExportShardSet set = read_export_shard_set(options.shards);
  const shards::ShardFile& first = set.shards.front();
  if (options.directional_share && !set.gltf.directional)
    fail("--directional-share: " + first.data_path + " is not a directional shard (export "
         "--directional --shard)");
  set.gltf.directional_share = set.gltf.directional_share || options.directional_share;
  const std::string extension = std::filesystem::path(options.output).extension().string();
  if (extension != ".glb" && extension != ".gltf")
    fail(options.output + ": output must be .glb or .gltf");
  for (const std::string& path : export_paths(options.output, set.gltf))
    prepare_output_file(path, options.force);

  if (set.gltf.denoise_direct) {
    try {
      require_oidn();  // before any work: the shards were made with --denoise
    } catch (const std::runtime_error& e) {
      fail(first.report_path + ": made with --denoise: " + e.what());
    }
  }
  const std::string scene_path = options.scene_path.empty() ? set.scene_path : options.scene_path;
  const std::string bake_dir = options.bake_dir.empty() ? set.bake_dir : options.bake_dir;
  const Scene scene = load_or_exit(scene_path);
  shards::check_recorded_hash(first, "scene_hash", scene_path, scene_hash(scene), "scene",
                              "baked");
  const BakeResult bake = load_bake(bake_dir, scene);
  shards::check_recorded_hash(first, "bake_hash", bake_dir, bake_hash(bake), "bake", "read");
  if (bake.illumination.width != set.width || bake.illumination.height != set.height)
    fail(bake_dir + ": atlas differs from the shards'");
  const DirectBand joined = join_export_shards(set);
  if (set.gltf.directional)
    set.gltf.direct_band = &joined;  // the merge makes the other terms' bands, as export does
  else
    set.gltf.direct_light = &joined.l0;
  if (!joined.unshadowed.empty()) set.gltf.direct_unshadowed = &joined.unshadowed;
  try {
    const ConsoleProgress console(options.quiet);
    const GltfExportInfo info =
        export_gltf(options.output, scene, bake, set.gltf, console.progress());
    if (options.quiet) return;
    std::printf("merged     %d export shards of %s (lightmap %dx%d, contents all%s)\n",
                first.count, scene_path.c_str(), set.width, set.height,
                set.gltf.directional ? ", directional" : "");
    for (const std::string& file : info.files) std::printf("wrote      %s\n", file.c_str());
  } catch (const Cancelled&) {
    std::fprintf(stderr, "lightbake: merge cancelled; nothing written\n");
    throw ExitCode{130};
  }
}

}  // namespace lb::app
