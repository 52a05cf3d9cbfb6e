#pragma once
// The shards given to `lightbake merge` (render tiles or pass-1 ray batches) must be a complete
// set: every index of 0..count-1 exactly once.

#include <cstddef>
#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <vector>

namespace lb::app {

// `indices[k]` is the shard index that the file `paths[k]` reports. Returns, per index, the
// position in `paths` of its file; fail()s naming the file for an index out of range or given
// twice, and names a missing index.
std::vector<size_t> shards_by_index(const std::vector<std::string>& paths,
                                    const std::vector<int>& indices, int count);

// PART.json beside PART.<data>.
std::string shard_report_path(const std::string& data_path);
// FNV-1a of a shard's data, 16 hex digits (its report records it).
std::string fnv1a_hex(std::span<const std::byte> bytes);
// fail()s naming `path`, the first key of `first` whose value `mine` does not share, both
// values and `first_path`: "... not a shard of the same `what`".
void check_same_settings(const nlohmann::json& mine, const nlohmann::json& first,
                         const std::string& path, const std::string& first_path,
                         const std::string& what);

}  // namespace lb::app
