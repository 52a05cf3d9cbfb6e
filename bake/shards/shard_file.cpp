#include "bake/shards/shard_file.h"

#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>

#include "bake/fnv1a.h"
#include "bake/input_file.h"
#include "bake/io/atomic_file.h"
#include "bake/json_text.h"

namespace lb::shards {

namespace {

using nlohmann::json;
constexpr const char* kMagic = "LBSHARD1";
constexpr const char* kFormat = "lightbake-shard";

[[noreturn]] void fail(const std::string& message) { throw std::runtime_error(message); }

void check_same(const json& mine, const json& first, const std::string& prefix,
                const std::string& path, const std::string& first_path, const std::string& what) {
  for (auto it = first.begin(); it != first.end(); ++it) {
    const json value = mine.is_object() ? mine.value(it.key(), json()) : json();
    const std::string key = prefix + it.key();
    if (it.value().is_object() && value.is_object()) {
      check_same(value, it.value(), key + ".", path, first_path, what);
    } else if (value != it.value()) {
      fail(path + ": " + key + " " + value.dump() + " differs from " + first_path + "'s " +
           it.value().dump() + ": not a shard of the same " + what);
    }
  }
}

// Per index 0..count-1, the position in `paths` of its file: each index once, in range.
std::vector<size_t> shards_by_index(const std::vector<std::string>& paths,
                                    const std::vector<int>& indices, int count) {
  constexpr size_t none = std::numeric_limits<size_t>::max();
  if (count < 1) fail(paths.front() + ": shard count " + std::to_string(count));
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

}  // namespace

std::string shard_report_path(const std::string& data_path) {
  return std::filesystem::path(data_path).replace_extension(".json").string();
}

bool is_shard_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char magic[8] = {};
  return in.read(magic, 8) && std::string(magic, 8) == kMagic;
}

void check_shard_extension(const std::string& path, const ShardKind& kind) {
  if (lowercase_extension(path) != kind.extension)
    fail(path + ": " + kind.label + " is written as " + kind.extension + " (" + kind.note + ")");
}

void write_shard(const std::string& data_path, const ShardKind& kind, int index, int count,
                 std::span<const std::byte> payload, const std::string& scene_path,
                 json settings, const json& measured) {
  Writer w;
  w.put_bytes(kMagic);
  w.put(uint32_t(kind.tag)), w.put(kind.version), w.put(uint32_t(index)), w.put(uint32_t(count));
  std::vector<std::byte> bytes = w.bytes();
  bytes.insert(bytes.end(), payload.begin(), payload.end());
  write_file_atomic(data_path, bytes);
  settings["shard_count"] = count;
  json report = {
      {"format", kFormat},
      {"kind", kind.name},
      {"version", kind.version},
      {"generator", "lightbake"},
      {"scene", scene_path},
      {"settings", std::move(settings)},
      {"shard", {{"index", index}, {"count", count}}},
      {"data",
       {{"file", std::filesystem::path(data_path).filename().string()},
        {"bytes", bytes.size()},
        {"fnv1a", fnv1a_hex(bytes)}}},
  };
  report.update(measured);
  write_text_atomic(shard_report_path(data_path), json_text(report, 2) + "\n");
}

ShardFile read_shard_report(const std::string& data_path, const ShardKind& kind) {
  ShardFile shard{data_path, shard_report_path(data_path), {}, 0, 0};
  std::ifstream in(shard.report_path);
  if (!in) fail(shard.report_path + ": cannot read the shard's report (written beside its data)");
  try {
    shard.report = json::parse(in);
    if (shard.report.at("format") != kFormat || shard.report.at("kind") != kind.name ||
        shard.report.at("version") != kind.version)
      throw std::invalid_argument("");
    shard.index = shard.report.at("shard").at("index").get<int>();
    shard.count = shard.report.at("shard").at("count").get<int>();
    shard.report.at("settings").get<json::object_t>();
    shard.report.at("data").get<json::object_t>();
  } catch (const std::exception&) {
    fail(shard.report_path + ": not the report of a `lightbake " + kind.command +
         " --shard` run of this version (" + std::to_string(kind.version) + ")");
  }
  return shard;
}

std::vector<ShardFile> read_shard_set(const std::vector<std::string>& paths,
                                      const ShardKind& kind) {
  if (paths.empty()) fail(std::string("merge: no ") + kind.name + " shards given");
  std::vector<ShardFile> shards;
  for (const std::string& path : paths) shards.push_back(read_shard_report(path, kind));
  const ShardFile& first = shards.front();
  std::vector<int> indices;
  for (const ShardFile& shard : shards) {
    check_same(shard.settings(), first.settings(), "", shard.data_path, first.data_path,
               kind.what);
    if (shard.settings().value("shard_count", json()) != shard.count)
      fail(shard.report_path + ": shard count " + std::to_string(shard.count) +
           " differs from its settings'");
    indices.push_back(shard.index);
  }
  std::vector<ShardFile> ordered;
  for (size_t k : shards_by_index(paths, indices, first.count)) ordered.push_back(shards[k]);
  return ordered;
}

void check_recorded_hash(const ShardFile& first, const std::string& key, const std::string& path,
                         const std::string& hash, const std::string& what,
                         const std::string& did) {
  const std::string recorded = first.settings().value(key, std::string());
  if (hash != recorded)
    fail(path + ": " + what + " hash " + hash + " differs from the shards' " + recorded + " (" +
         first.report_path + "): not the " + what + " they " + did);
}

Reader open_shard_payload(const ShardFile& shard, const ShardKind& kind) {
  Reader r(shard.data_path);
  const json& data = shard.report.at("data");
  if (r.size() != data.value("bytes", uint64_t(0)) ||
      fnv1a_hex(r.bytes()) != data.value("fnv1a", std::string()))
    fail(shard.data_path + ": its size or FNV-1a differs from " + shard.report_path +
         "'s: not the data that report describes");
  r.expect_magic(kMagic);
  if (r.get<uint32_t>() != uint32_t(kind.tag)) r.fail(std::string("not ") + kind.label);
  if (r.get<uint32_t>() != kind.version) r.fail("unknown version");
  const uint32_t index = r.get<uint32_t>(), count = r.get<uint32_t>();
  if (index != uint32_t(shard.index) || count != uint32_t(shard.count))
    r.fail("shard " + std::to_string(index) + " of " + std::to_string(count) + ", its report's " +
           std::to_string(shard.index) + " of " + std::to_string(shard.count));
  return r;
}

}  // namespace lb::shards
