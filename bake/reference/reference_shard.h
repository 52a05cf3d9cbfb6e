#pragma once
// Reference shards (`lightbake reference SCENE --shard i/n -o PART.refshard`) in the shard
// container (bake/shards/shard_file.h) and their merge (`lightbake merge PART.refshard... -o
// ref.exr|png`). A shard renders the passes k with k mod n = i (reference.h):
//
//   payload   the film's fixed-point sums and pass means (film_io.h)
//   settings  scene_hash, camera, size, spp, seed, terms, light paths, roulette, max depth, tile
//             and block sizes, tone, window; the report also holds "passes", "rays",
//             "cpu_seconds" and "wall_seconds"
//
// Merge adds the films (integer sums: any order): the image and report of the unsharded render,
// with its bits (the report's noise estimate too; only the seconds differ).

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "bake/reference/film.h"
#include "bake/reference/reference.h"
#include "bake/shards/shard_file.h"

namespace lb::reference {

inline constexpr shards::ShardKind kReferenceShard{
    shards::ShardTag::reference, "reference", "a reference shard",
    "its exact sums; lightbake merge makes the image", ".refshard", "reference", "render", 1};
inline constexpr int kMaxReferenceShards = 65536;  // as render tiles' shards

// What every shard of one render shares (compared key by key by merge).
nlohmann::json reference_shard_settings(const std::string& scene_hash, const std::string& camera,
                                        const ReferenceParams& params,
                                        const std::string& tone_curve, float exposure);

// Writes PART.refshard, then PART.json. `settings`: reference_shard_settings.
void write_reference_shard(const std::string& data_path, const std::string& scene_path,
                           const nlohmann::json& settings, const ReferenceParams& params,
                           const Film& film, const ReferenceStats& stats);

struct MergedReference {
  ReferenceParams params;   // of the whole render (shard 0 of 1)
  Film film;                // every pass
  ReferenceStats stats;     // rays and CPU seconds summed, wall seconds the longest shard's
  nlohmann::json settings;  // the shards' (camera, tone)
  std::string scene_path;   // as the first shard recorded it
  std::string report_path;  // the first shard's
  int shard_count = 0;
};

// Throws (one line naming the file) for a missing or repeated shard, shards of another scene,
// setting or count, and data that is not what its report describes or not its shard's passes.
MergedReference merge_reference_shards(const std::vector<std::string>& paths);

}  // namespace lb::reference
