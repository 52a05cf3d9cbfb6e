#include "app/export_shard.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "app/console_progress.h"
#include "app/load.h"
#include "app/output_path.h"
#include "app/radiance_output.h"
#include "app/shard_set.h"
#include "bake/io/atomic_file.h"
#include "bake/export/gltf_export.h"
#include "bake/json_text.h"
#include "bake/lightmap/lightmap.h"
#include "bake/lightmap/texel_footprint.h"
#include "bake/pipeline/bake_io.h"
#include "bake/binary_file.h"

namespace lb::app {

namespace {

using nlohmann::json;
constexpr const char* kMagic = "LBTEXSH1";
constexpr const char* kExportShardFormat = "lightbake-export-shard";
// 2: one range of rows per shard, recorded in the header (1: bands b with b mod n = i).
constexpr uint32_t kVersion = 2;

json shared_settings(const std::string& scene_hash, const std::string& bake_hash,
                     const ExportShardOptions& o, int width, int height) {
  return {{"scene_hash", scene_hash},
          {"bake_hash", bake_hash},
          {"contents", "all"},
          {"direct_samples", o.direct_side},
          {"lightmap_format", o.lightmap_format},
          {"lightmap_encoding", o.lightmap_encoding},
          {"atlas_width", width},
          {"atlas_height", height},
          {"shard_count", o.count}};
}

// The shard's rows into `direct` (width x height); returns them.
TexelRows read_shard_rows(const ShardFile& shard, int width, int height,
                          std::vector<vec3>& direct) {
  Reader r = open_shard_data(shard);
  try {
    r.expect_magic(kMagic);
    if (r.get<uint32_t>() != kVersion) r.fail("unknown version");
    const uint32_t w = r.get<uint32_t>(), h = r.get<uint32_t>();
    const uint32_t index = r.get<uint32_t>(), count = r.get<uint32_t>();
    const uint32_t begin = r.get<uint32_t>(), end = r.get<uint32_t>();
    if (w != uint32_t(width) || h != uint32_t(height) || index != uint32_t(shard.index) ||
        count != uint32_t(shard.count))
      r.fail("atlas or shard differs from the report's");
    if (begin > end || end > h) r.fail("rows out of the atlas");
    const TexelRows rows{int(begin), int(end)};
    for (int j = rows.begin; j < rows.end; ++j) {
      const std::vector<float> row = r.get_array<float>(size_t(width) * 3);
      for (int i = 0; i < width; ++i)
        direct[size_t(j) * size_t(width) + size_t(i)] =
            vec3(row[size_t(i) * 3], row[size_t(i) * 3 + 1], row[size_t(i) * 3 + 2]);
    }
    r.expect_end();
    return rows;
  } catch (const std::runtime_error& e) {
    fail(e.what());
  }
}

}  // namespace

bool is_texel_shard_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char magic[8] = {};
  return in.read(magic, 8) && std::string(magic, 8) == kMagic;
}

void write_export_shard(const ExportShardOptions& options) {
  if (options.bake_dir.empty())
    fail("export --shard: give the bake directory (bake once, then every shard reads it)");
  if (lowercase_extension(options.output) != kTexelShardExtension)
    fail(options.output + ": an export shard is written as " + std::string(kTexelShardExtension) +
         " (its texels; lightbake merge writes the glTF)");
  try {
    parse_lightmap_format(options.lightmap_format);
    parse_lightmap_encoding(options.lightmap_encoding);
  } catch (const std::invalid_argument& e) {
    fail(e.what());
  }
  prepare_output_file(options.output, options.force);
  prepare_output_file(shard_report_path(options.output), options.force);

  const auto start = std::chrono::steady_clock::now();
  const Scene scene = load_or_exit(options.scene_path);
  const BakeResult bake = load_bake(options.bake_dir, scene);
  LightmapParams params;  // as export_gltf sets them
  params.contents = LightmapContents::all;
  params.direct_side = options.direct_side;
  params.seed = bake.seed;
  params.shard = options.index;
  params.shard_count = options.count;
  const ConsoleProgress console(options.quiet);  // Ctrl-C cancels: nothing is written
  const Lightmap lightmap = bake_lightmap(scene, bake, params, console.progress());

  Writer w;
  w.put_bytes(kMagic);
  w.put(kVersion);
  w.put(uint32_t(lightmap.width)), w.put(uint32_t(lightmap.height));
  w.put(uint32_t(options.index)), w.put(uint32_t(options.count));
  const TexelRows rows = lightmap.direct_rows;
  w.put(uint32_t(rows.begin)), w.put(uint32_t(rows.end));
  for (int j = rows.begin; j < rows.end; ++j)
    for (int i = 0; i < lightmap.width; ++i) {
      const vec3 v = lightmap.direct[size_t(j) * size_t(lightmap.width) + size_t(i)];
      w.put(v.x), w.put(v.y), w.put(v.z);
    }
  write_file_atomic(options.output, w.bytes());
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const json report = {
      {"format", kExportShardFormat},
      {"version", kVersion},
      {"generator", "lightbake"},
      {"scene", options.scene_path},
      {"bake", options.bake_dir},
      {"settings", shared_settings(scene_hash(scene), bake_hash(bake), options, lightmap.width,
                                   lightmap.height)},
      {"shard", {{"index", options.index}, {"count", options.count}}},
      {"rows", {{"begin", rows.begin}, {"end", rows.end}}},  // node rows [begin, end)
      {"data",
       {{"file", std::filesystem::path(options.output).filename().string()},
        {"bytes", w.bytes().size()},
        {"fnv1a", fnv1a_hex(w.bytes())}}},
      // Its rows' rays and the cell row above them, which the shard before also traces.
      {"shadow_rays", lightmap.shadow_rays},
      // The points estimated, the work the rows were split by (those facing no light trace no
      // shadow ray).
      {"points", lightmap.direct_points},
      {"seconds", seconds},
  };
  write_text_atomic(shard_report_path(options.output), json_text(report, 2) + "\n");
  if (options.quiet) return;
  std::printf(
      "export     shard %d/%d: direct light of lightmap rows %d-%d of %d (%dx%d), %llu "
      "shadow rays, %.2f s\n",
      options.index, options.count, rows.begin, rows.end - 1, lightmap.height, lightmap.width,
      lightmap.height, (unsigned long long)lightmap.shadow_rays, seconds);
  std::printf("wrote      %s, %s\n", options.output.c_str(),
              shard_report_path(options.output).c_str());
}

void merge_export_shards(const ExportMergeOptions& options) {
  std::vector<ShardFile> shards;
  for (const std::string& path : options.shards)
    shards.push_back(read_shard_file(path, kExportShardFormat, kVersion, "export"));
  const std::vector<size_t> by_index = check_shard_files(shards, "export");
  const ShardFile& first = shards.front();
  const json& settings = first.report.at("settings");

  GltfExportOptions gltf;
  gltf.contents = LightmapContents::all;
  int width = 0, height = 0;
  try {
    gltf.format = parse_lightmap_format(settings.at("lightmap_format").get<std::string>());
    gltf.encoding =
        parse_lightmap_encoding(settings.at("lightmap_encoding").get<std::string>());
    gltf.direct_side = settings.at("direct_samples").get<int>();
    width = settings.at("atlas_width").get<int>(), height = settings.at("atlas_height").get<int>();
    if (width < 0 || height < 0 || width > 65536 || height > 65536)
      throw std::invalid_argument("");
  } catch (const std::exception&) {
    fail(first.report_path + ": settings out of range or of another lightbake");
  }
  const std::string extension = std::filesystem::path(options.output).extension().string();
  if (extension != ".glb" && extension != ".gltf")
    fail(options.output + ": output must be .glb or .gltf");
  for (const std::string& path : export_paths(options.output, gltf))
    prepare_output_file(path, options.force);

  const std::string scene_path =
      options.scene_path.empty() ? first.report.value("scene", std::string()) : options.scene_path;
  const std::string bake_dir =
      options.bake_dir.empty() ? first.report.value("bake", std::string()) : options.bake_dir;
  const Scene scene = load_or_exit(scene_path);
  const std::string hash = scene_hash(scene);
  if (hash != settings.at("scene_hash"))
    fail(scene_path + ": scene hash " + hash + " differs from the shards' " +
         settings.at("scene_hash").dump() + " (" + first.report_path +
         "): not the scene they baked");
  BakeResult bake;
  try {
    bake = load_bake(bake_dir, scene);
  } catch (const std::exception& e) {
    fail(e.what());
  }
  if (bake_hash(bake) != settings.at("bake_hash"))
    fail(bake_dir + ": bake hash " + bake_hash(bake) + " differs from the shards' " +
         settings.at("bake_hash").dump() + " (" + first.report_path + "): not the bake they read");
  if (bake.illumination.width != width || bake.illumination.height != height)
    fail(bake_dir + ": atlas differs from the shards'");

  std::vector<vec3> direct(size_t(width) * size_t(height), vec3(0.0f));
  // Shard i's rows follow shard i - 1's; the last ends at the atlas's last row.
  int next_row = 0;
  for (int i = 0; i < first.count; ++i) {
    const ShardFile& shard = shards[by_index[size_t(i)]];
    const TexelRows rows = read_shard_rows(shard, width, height, direct);
    if (rows.begin != next_row)
      fail(shard.data_path + ": its rows begin at " + std::to_string(rows.begin) + ", not at " +
           std::to_string(next_row) +
           (i > 0 ? " where shard " + std::to_string(i - 1) + "'s end" : std::string()) +
           ": not a shard of the same partition");
    next_row = rows.end;
  }
  if (next_row != height)
    fail(shards[by_index.back()].data_path + ": the last shard's rows end at " +
         std::to_string(next_row) + ", not at the atlas's " + std::to_string(height));
  gltf.direct_light = &direct;
  try {
    const ConsoleProgress console(options.quiet);
    const GltfExportInfo info = export_gltf(options.output, scene, bake, gltf, console.progress());
    if (options.quiet) return;
    std::printf("merged     %d export shards of %s (lightmap %dx%d, contents all)\n", first.count,
                scene_path.c_str(), width, height);
    for (const std::string& file : info.files) std::printf("wrote      %s\n", file.c_str());
  } catch (const Cancelled&) {
    std::fprintf(stderr, "lightbake: merge cancelled; nothing written\n");
    throw ExitCode{130};
  }
}

}  // namespace lb::app
