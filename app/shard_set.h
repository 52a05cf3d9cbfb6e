#pragma once
// The shards given to `lightbake merge` (render tiles, pass-1 ray batches, reference passes,
// export texel rows) must be a complete set: every index of 0..count-1 exactly once. And what the
// binary shard kinds share: PART.data beside PART.json, whose "settings" every shard of one run
// has equal and whose "data" records the data's size and FNV-1a.

#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <vector>

#include "bake/binary_file.h"

namespace lb::app {

// `indices[k]` is the shard index that the file `paths[k]` reports. Returns, per index, the
// position in `paths` of its file; fail()s naming the file for an index out of range or given
// twice, and names a missing index.
std::vector<size_t> shards_by_index(const std::vector<std::string>& paths,
                                    const std::vector<int>& indices, int count);

// A merged image's checks before any work: .exr or .png, and neither it nor its report
// (returned: OUTPUT.json) replaces a file lightbake did not write unless `force`.
std::string prepare_merged_image(const std::string& output, bool force);
// PART.json beside PART.<data>.
std::string shard_report_path(const std::string& data_path);
// fail()s naming `path`, the first key of `first` whose value `mine` does not share, both
// values and `first_path`: "... not a shard of the same `what`".
void check_same_settings(const nlohmann::json& mine, const nlohmann::json& first,
                         const std::string& path, const std::string& first_path,
                         const std::string& what);

struct ShardFile {
  std::string data_path, report_path;
  nlohmann::json report;
  int index = 0, count = 0;
};
// PART.json of `data_path`; fail()s naming it unless it is the report of `command` (its
// "format" and "version" as given) with a shard index, count and settings.
ShardFile read_shard_file(const std::string& data_path, const std::string& format, uint32_t version,
                          const std::string& command);
// The shards' complete set, each settings equal to the first's (`what`: "render", ...) and
// holding its shard count; returns, per index, the position of its shard.
std::vector<size_t> check_shard_files(const std::vector<ShardFile>& shards,
                                      const std::string& what);
// A reader over PART's data; fail()s naming it when its size or FNV-1a is not its report's.
Reader open_shard_data(const ShardFile& shard);

}  // namespace lb::app
