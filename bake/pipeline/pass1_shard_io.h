#pragma once
// Pass-1 shards (`lightbake bake SCENE --shard i/n -o PART.pass1`) in the shard container
// (bake/shards/shard_file.h) and their merge (`lightbake merge PART.pass1... -o BAKE`).
//
//   payload   u32 atlas width, u32 height, the tallies (illumination::FixedTally: i64 sent[3],
//             deposited[3], absorbed[3], escaped[3], direct[3], unmapped[3], u64 casts, rays,
//             emitter_hits), u64 n, then the n atlas nodes with any sum not 0, in node order:
//             u64 node, i64 power[3], i64 weight (caustics light few texels: a shard is small);
//             with light groups (bake/light_groups.h), u32 their count, then for each of the n
//             nodes in that order, i64 power[3] per group (without groups: nothing); with
//             the `directional` setting, for each of the n nodes in that order, i64 l1[9]
//             (Pass1Sums::node_l1; without it: nothing).
//   settings  scene_hash, atlas {width, height}, bake (every bake setting, as a manifest
//             records them); the report also holds "rays" and "seconds".
//
// Merge sums the shards' data and finishes the bake (bake_from_pass1_sums): the bits of the
// unsharded bake with the same settings.

#include <string>
#include <vector>

#include "bake/pipeline/bake.h"
#include "bake/shards/shard_file.h"

namespace lb {

inline constexpr shards::ShardKind kPass1Shard{
    shards::ShardTag::pass1, "pass1", "a pass-1 shard",
    "its report .json beside it; lightbake merge makes the bake", ".pass1", "bake", "bake", 1};

// Writes PART.pass1 then PART.json. `seconds`: the shard's run time (recorded, not checked).
void write_pass1_shard(const std::string& data_path, const Scene& scene, const BakeParams& params,
                       int index, int count, const Pass1Shard& shard, double seconds);

// One bake's complete set of pass-1 shards, in index order, and the settings they share.
struct Pass1ShardSet {
  std::vector<shards::ShardFile> shards;
  std::string scene_path;  // where the first shard's scene was
  BakeParams params;
};
// Throws naming the file for a missing, repeated or foreign shard (shard_file.h).
Pass1ShardSet read_pass1_shard_set(const std::vector<std::string>& paths);

// The bake of the set's summed pass 1: throws naming `scene_path` when `scene` is not the one
// the shards baked, and naming a shard whose data is truncated, altered or of another atlas.
BakeResult bake_from_pass1_shards(const Pass1ShardSet& set, const Scene& scene,
                                  const std::string& scene_path, const Progress& progress = {});

}  // namespace lb
