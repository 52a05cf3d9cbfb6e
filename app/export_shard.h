#pragma once
// `lightbake export SCENE BAKE --contents all --shard i/n -o PART.texshard` and `lightbake merge
// PART.texshard... -o out.glb|gltf`: the options, loading and console of the export's shards;
// the format and the join are bake/export/export_shard.h's.

#include <string>
#include <vector>

namespace lb::app {

struct ExportShardOptions {
  std::string scene_path;
  std::string bake_dir;
  std::string output;  // PART.texshard
  std::string lightmap_format = "exr";
  std::string lightmap_encoding = "srgb";
  int direct_side = 0;
  bool denoise = false;            // recorded: the merge denoises the joined direct term
  bool directional = false;        // the direct term's L1 too (export --directional)
  bool directional_share = false;  // recorded: the merge writes s (--directional-share)
  int shadow_side = 0;             // --shadow-rays (LightmapParams::shadow_side), recorded
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
  bool directional_share = false;   // s in the file (directional shards only)
  bool force = false;
  bool quiet = false;
};

// Refuses (one line naming the file, exit 1, nothing written) a missing or repeated shard,
// shards of another scene, bake, setting or count, and data that is not what its report
// describes.
void merge_export_shards(const ExportMergeOptions& options);

}  // namespace lb::app
