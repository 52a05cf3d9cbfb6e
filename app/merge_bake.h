#pragma once
// `lightbake merge PART.pass1... -o BAKE`: joins the shards of pass 1 (`lightbake bake --shard
// i/n`) and finishes the bake locally: pass 1's maps, pass 2 and the soft-light map. The
// result has the bits of `lightbake bake SCENE -o BAKE` with the same settings (its manifest
// differs only in what the run measured: seconds, peak memory).

#include <string>
#include <vector>

namespace lb::app {

struct BakeMergeOptions {
  std::vector<std::string> shards;  // PART.pass1 files, their .json beside them
  std::string output_dir = "bake";
  std::string scene_path;  // "" = the path the shards recorded
  bool force = false;      // also write into a folder that holds no bake
  bool quiet = false;
};

// Refuses (one line naming the file, exit 1) shards of another scene, settings, seed, count or
// atlas, a missing or a repeated shard, data that does not match its report.
void merge_bake_shards(const BakeMergeOptions& options);

}  // namespace lb::app
