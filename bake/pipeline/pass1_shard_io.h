#pragma once
// A shard of pass 1 on disk (`lightbake bake SCENE --shard i/n -o PART.pass1`), two files
// written atomically (bake/io/atomic_file.h), the data first:
//
//   PART.pass1  "LBPASS1S", u32 version, u32 atlas width, u32 height, the tallies
//               (illumination::FixedTally: i64 sent[3], deposited[3], absorbed[3], escaped[3],
//               direct[3], unmapped[3], u64 casts, rays, emitter_hits), u64 n, then the n
//               atlas nodes with any sum not 0, in node order: u64 node, i64 power[3],
//               i64 weight (caustics light few texels: a shard is small). Little-endian.
//   PART.json   {"format": "lightbake-pass1-shard", "version", "generator": "lightbake",
//               "scene" (path), "scene_hash", "seed", "settings" (every bake setting, as a
//               manifest records them), "shard": {"index", "count"}, "atlas": {"width",
//               "height"}, "data": {"file", "bytes", "fnv1a"}, "rays", "seconds"}
//
// `lightbake merge` reads the reports, refuses shards that do not belong together, sums the
// data and finishes the bake (bake_from_pass1_sums).

#include <nlohmann/json.hpp>
#include <string>

#include "bake/pipeline/bake.h"

namespace lb {

inline constexpr const char* kPass1ShardExtension = ".pass1";

// PART.json for PART.pass1.
std::string pass1_shard_report_path(const std::string& data_path);
// The file starts with the shard magic (so a rerun may replace it).
bool is_pass1_shard_file(const std::string& path);

struct Pass1ShardReport {
  std::string data_path;    // PART.pass1
  std::string report_path;  // PART.json
  nlohmann::json report;
  int index = 0, count = 0;
};

// Writes PART.pass1 then PART.json. `seconds`: the shard's run time (recorded, not checked).
void write_pass1_shard(const std::string& data_path, const Scene& scene, const BakeParams& params,
                       int index, int count, const Pass1Shard& shard, double seconds);

// Reads PART.json; throws std::runtime_error naming it when it is missing or not a shard's.
Pass1ShardReport read_pass1_shard_report(const std::string& data_path);

// What every shard of one bake shares (scene hash, seed, settings, count, atlas size): two
// shards belong together when these are equal.
nlohmann::json pass1_shard_shared(const nlohmann::json& report);

// Adds PART.pass1's sums into `sums`; throws std::runtime_error naming the file when it is
// truncated, altered (its size or FNV-1a differs from the report's) or of another atlas size.
void add_pass1_shard_sums(const Pass1ShardReport& shard, illumination::Pass1Sums& sums);

}  // namespace lb
