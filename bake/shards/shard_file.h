#pragma once
// The one shard container of every sharded command (`lightbake bake|render|reference|export
// --shard i/n`): a kind supplies its payload bytes and its settings; framing, report, hash and the
// complete-set check are here, once. Two files, written atomically, the data first:
//
//   PART.<ext>  "LBSHARD1", u32 kind tag, u32 payload version, u32 shard index, u32 count, then
//               the kind's payload. Little-endian.
//   PART.json   {"format": "lightbake-shard", "kind", "version", "generator": "lightbake",
//               "scene" (path), "settings" (the kind's, with "shard_count"), "shard": {"index",
//               "count"}, "data": {"file", "bytes", "fnv1a"}, then what the kind measured}
//
// Shards belong together when their settings are equal key by key. Every error is a
// std::runtime_error whose one line names the file.

#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <vector>

#include "bake/binary_file.h"

namespace lb::shards {

// The header's kind tags, one per kind, so no two kinds' payloads are taken for each other.
enum class ShardTag : uint32_t { pass1 = 1, reference = 2, export_texels = 3, render = 4 };

struct ShardKind {
  ShardTag tag;           // in the header: what the payload is
  const char* name;       // the report's "kind"
  const char* label;      // "a pass-1 shard", in messages
  const char* note;       // why that extension: what PART holds, what merge makes of it
  const char* extension;  // of PART, with its dot
  const char* command;    // the `lightbake COMMAND --shard` that writes it
  const char* what;       // in "not a shard of the same WHAT"
  uint32_t version;       // of the payload
};

// PART.json beside PART.<ext>.
std::string shard_report_path(const std::string& data_path);
// The file starts with the container's magic (so a rerun may replace it).
bool is_shard_file(const std::string& path);
// Throws unless `path` ends in the kind's extension (any case).
void check_shard_extension(const std::string& path, const ShardKind& kind);

// Writes PART (header + payload), then PART.json: `settings` gains "shard_count"; `measured`'s
// keys (rays, seconds, ...) follow the container's.
void write_shard(const std::string& data_path, const ShardKind& kind, int index, int count,
                 std::span<const std::byte> payload, const std::string& scene_path,
                 nlohmann::json settings,
                 const nlohmann::json& measured = nlohmann::json::object());

struct ShardFile {
  std::string data_path, report_path;
  nlohmann::json report;
  int index = 0, count = 0;
  const nlohmann::json& settings() const { return report.at("settings"); }
};

// PART.json of `data_path`, a report of `kind` at its version.
ShardFile read_shard_report(const std::string& data_path, const ShardKind& kind);

// The reports of `paths`, one complete set of `kind` (settings equal to the first's key by key,
// dotted into objects: a difference names the key, both values and both files; each index of
// its count once), in index order.
std::vector<ShardFile> read_shard_set(const std::vector<std::string>& paths,
                                      const ShardKind& kind);

// Throws naming `path` unless `hash`, of the file or folder at `path` given to merge, is the
// one the shards' settings record under `key`: "... not the `what` they `did`".
void check_recorded_hash(const ShardFile& first, const std::string& key, const std::string& path,
                         const std::string& hash, const std::string& what,
                         const std::string& did);

// A reader at PART's payload: its size and FNV-1a are its report's, its header the report's
// kind, version, index and count.
Reader open_shard_payload(const ShardFile& shard, const ShardKind& kind);

}  // namespace lb::shards
