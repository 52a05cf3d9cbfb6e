#include "app/shard_set.h"

#include <filesystem>
#include <limits>

#include "app/commands.h"
#include "bake/pipeline/binary_file.h"

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

std::string shard_report_path(const std::string& data_path) {
  return std::filesystem::path(data_path).replace_extension(".json").string();
}

std::string fnv1a_hex(std::span<const std::byte> bytes) {
  Fnv1a hash;
  hash.add(bytes.data(), bytes.size());
  return hex_digits(hash.value());
}

void check_same_settings(const nlohmann::json& mine, const nlohmann::json& first,
                         const std::string& path, const std::string& first_path,
                         const std::string& what) {
  for (auto it = first.begin(); it != first.end(); ++it)
    if (mine.value(it.key(), nlohmann::json()) != it.value())
      fail(path + ": " + it.key() + " " + mine.value(it.key(), nlohmann::json()).dump() +
           " differs from " + first_path + "'s " + it.value().dump() + ": not a shard of the same " +
           what);
}

}  // namespace lb::app
