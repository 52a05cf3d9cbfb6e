#pragma once
// Shards of the reference renderer (`lightbake reference SCENE --shard i/n -o PART.refshard`)
// and their merge (`lightbake merge PART.refshard... -o ref.exr|png`). A shard renders the passes
// k with k mod n = i (bake/reference/reference.h) and writes two files, the data first:
//
//   PART.refshard  the film's fixed-point sums and pass means (bake/reference/film_io.h)
//   PART.json      {"format": "lightbake-reference-shard", "version", "generator": "lightbake",
//                  "scene" (path), "camera", "settings" (scene_hash, camera, size, spp, seed,
//                  terms, light paths, roulette, max depth, tile and block sizes, tone),
//                  "shard": {"index", "count"}, "data": {"file", "bytes", "fnv1a"}, "rays",
//                  "cpu_seconds", "wall_seconds"}
//
// Merge adds the films (integer sums: any order) and writes the image and the report of the
// unsharded render, with its bits (the report's noise estimate too; only the seconds differ).

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "bake/reference/reference.h"

namespace lb::app {

inline constexpr const char* kReferenceShardExtension = ".refshard";
inline constexpr int kMaxReferenceShards = 65536;  // as render tiles' shards

// The file starts with the film magic (so a rerun may replace it).
bool is_reference_shard_file(const std::string& path);

// What every shard of one render shares (compared key by key by merge).
nlohmann::json reference_shard_settings(const std::string& scene_hash, const std::string& camera,
                                        const reference::ReferenceParams& params,
                                        const std::string& tone_curve, float exposure);

// Writes PART.refshard, then PART.json. `settings`: reference_shard_settings.
void write_reference_shard(const std::string& data_path, const std::string& scene_path,
                           const nlohmann::json& settings, const reference::ReferenceParams& params,
                           const reference::Film& film, const reference::ReferenceStats& stats);

struct ReferenceMergeOptions {
  std::vector<std::string> shards;  // PART.refshard files, their .json beside them
  std::string output;               // .exr or .png; its report beside it (.json)
  bool force = false;
};

// Refuses (one line naming the file, exit 1, nothing written) a missing or repeated shard,
// shards of another scene, setting or count, and data that is not what its report describes.
void merge_reference_shards(const ReferenceMergeOptions& options);

}  // namespace lb::app
