#pragma once
// Shards of the export's direct-light bake (`lightbake export SCENE BAKE --contents all --shard
// i/n -o PART.texshard`) and their merge (`lightbake merge PART.texshard... -o out.glb|gltf`).
// A shard bakes the direct term of one range of the lightmap's node rows, about 1/n of the work
// (bake/lightmap/texel_footprint.h, partition_texel_rows: every node it bakes has the bits of
// the unsharded export's) and writes two files, the data first:
//
//   PART.texshard  "LBTEXSH1", u32 version (2), u32 atlas width, height, u32 shard, count, u32
//                  first row, end row (one past the last), then the direct term (3 x f32,
//                  W/(sr m^2)) of those node rows, in row order. Little-endian.
//   PART.json      {"format": "lightbake-export-shard", "version", "generator": "lightbake",
//                  "scene" (path), "bake" (directory), "settings" (scene_hash, bake_hash,
//                  direct_samples, lightmap_format, atlas size, shard_count),
//                  "shard": {"index", "count"}, "rows": {"begin", "end"},
//                  "data": {"file", "bytes", "fnv1a"}, "shadow_rays", "points", "seconds"}
//
// Merge loads the scene and the bake (from the recorded paths, or --scene and --bake; their
// content hashes must match), joins the rows (shard i's must begin where shard i - 1's end)
// and writes the export: the glTF and its EXR/HDR have the bytes of `lightbake export SCENE
// BAKE --contents all` with the same settings. Version 1 shards (bands b mod n = i) are refused.

#include <string>
#include <vector>

namespace lb::app {

inline constexpr const char* kTexelShardExtension = ".texshard";
inline constexpr int kMaxExportShards = 65536;

// The file starts with the shard magic (so a rerun may replace it).
bool is_texel_shard_file(const std::string& path);

struct ExportShardOptions {
  std::string scene_path;
  std::string bake_dir;
  std::string output;  // PART.texshard
  std::string lightmap_format = "exr";
  std::string lightmap_encoding = "srgb";
  int direct_side = 0;
  int index = 0, count = 1;
  bool force = false;
  bool quiet = false;
};

// Bakes the shard's rows and writes PART.texshard and PART.json.
void write_export_shard(const ExportShardOptions& options);

struct ExportMergeOptions {
  std::vector<std::string> shards;  // PART.texshard files, their .json beside them
  std::string output;               // .glb or .gltf
  std::string scene_path;           // "" = the path the shards recorded
  std::string bake_dir;             // "" = the directory the shards recorded
  bool force = false;
  bool quiet = false;
};

// Refuses (one line naming the file, exit 1, nothing written) a missing or repeated shard,
// shards of another scene, bake, setting or count, and data that is not what its report
// describes.
void merge_export_shards(const ExportMergeOptions& options);

}  // namespace lb::app
