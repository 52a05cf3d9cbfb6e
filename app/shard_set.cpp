#include "app/shard_set.h"

#include <filesystem>
#include <fstream>
#include <limits>

#include "app/commands.h"
#include "app/output_path.h"
#include "app/radiance_output.h"

namespace lb::app {

std::vector<size_t> shards_by_index(const std::vector<std::string>& paths,
                                    const std::vector<int>& indices, int count) {
  constexpr size_t none = std::numeric_limits<size_t>::max();
  std::vector<size_t> by_index(size_t(count), none);
  for (size_t k = 0; k < paths.size(); ++k) {
    const int index = indices[k];
    if (index < 0 || index >= count)
      fail(paths[k] + ": shard " + std::to_string(index) + " of " + std::to_string(count));
    if (by_index[size_t(index)] != none)
      fail(paths[k] + ": shard " + std::to_string(index) + " given twice (also " +
           paths[by_index[size_t(index)]] + ")");
    by_index[size_t(index)] = k;
  }
  for (int i = 0; i < count; ++i)
    if (by_index[size_t(i)] == none)
      fail("shard " + std::to_string(i) + " of " + std::to_string(count) + " is missing");
  return by_index;
}

std::string prepare_merged_image(const std::string& output, bool force) {
  if (!is_radiance_image_path(output)) fail(output + ": output must be .exr or .png");
  const std::string report_path = shard_report_path(output);
  prepare_output_file(output, force);
  prepare_output_file(report_path, force);
  return report_path;
}

std::string shard_report_path(const std::string& data_path) {
  return std::filesystem::path(data_path).replace_extension(".json").string();
}

void check_same_settings(const nlohmann::json& mine, const nlohmann::json& first,
                         const std::string& path, const std::string& first_path,
                         const std::string& what) {
  for (auto it = first.begin(); it != first.end(); ++it)
    if (mine.value(it.key(), nlohmann::json()) != it.value())
      fail(path + ": " + it.key() + " " + mine.value(it.key(), nlohmann::json()).dump() +
           " differs from " + first_path + "'s " + it.value().dump() +
           ": not a shard of the same " + what);
}

ShardFile read_shard_file(const std::string& data_path, const std::string& format, uint32_t version,
                          const std::string& command) {
  ShardFile shard{data_path, shard_report_path(data_path), {}, 0, 0};
  std::ifstream in(shard.report_path);
  if (!in) fail(shard.report_path + ": cannot read the shard's report (written beside its data)");
  try {
    shard.report = nlohmann::json::parse(in);
    if (shard.report.at("format") != format || shard.report.at("version") != version)
      throw std::invalid_argument("");
    shard.index = shard.report.at("shard").at("index").get<int>();
    shard.count = shard.report.at("shard").at("count").get<int>();
    shard.report.at("settings").get<nlohmann::json::object_t>();
  } catch (const std::exception&) {
    fail(shard.report_path + ": not the report of a `lightbake " + command +
         " --shard` run of this version (" + std::to_string(version) + ")");
  }
  return shard;
}

std::vector<size_t> check_shard_files(const std::vector<ShardFile>& shards,
                                      const std::string& what) {
  const ShardFile& first = shards.front();
  const nlohmann::json& settings = first.report.at("settings");
  std::vector<std::string> paths;
  std::vector<int> indices;
  for (const ShardFile& shard : shards) {
    check_same_settings(shard.report.at("settings"), settings, shard.data_path, first.data_path,
                        what);
    if (shard.count != settings.value("shard_count", 0))
      fail(shard.report_path + ": shard count " + std::to_string(shard.count) +
           " differs from its settings'");
    paths.push_back(shard.data_path);
    indices.push_back(shard.index);
  }
  return shards_by_index(paths, indices, first.count);
}

Reader open_shard_data(const ShardFile& shard) {
  try {
    Reader r(shard.data_path);
    const nlohmann::json& data = shard.report.at("data");
    if (r.size() != data.value("bytes", uint64_t(0)) ||
        fnv1a_hex(r.bytes()) != data.value("fnv1a", std::string()))
      fail(shard.data_path + ": its size or FNV-1a differs from " + shard.report_path +
           "'s: not the data that report describes");
    return r;
  } catch (const std::runtime_error& e) {
    fail(e.what());
  }
}

}  // namespace lb::app
