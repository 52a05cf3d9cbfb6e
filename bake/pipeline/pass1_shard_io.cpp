#include "bake/pipeline/pass1_shard_io.h"

#include <filesystem>
#include <fstream>
#include <span>
#include <stdexcept>

#include "bake/io/atomic_file.h"
#include "bake/json_text.h"
#include "bake/pipeline/bake_io.h"
#include "bake/binary_file.h"

namespace lb {

namespace {

using illumination::add_checked;
using illumination::FixedTally;
using illumination::Pass1Sums;
using nlohmann::json;

constexpr const char* kMagic = "LBPASS1S";
constexpr uint32_t kVersion = 1;

void put_tally(Writer& w, const FixedTally& t) {
  for (const int64_t* a : {t.sent, t.deposited, t.absorbed, t.escaped, t.direct, t.unmapped})
    for (int c = 0; c < 3; ++c) w.put(a[c]);
  w.put(t.casts), w.put(t.rays), w.put(t.emitter_hits);
}

FixedTally get_tally(Reader& r) {
  FixedTally t;
  for (int64_t* a : {t.sent, t.deposited, t.absorbed, t.escaped, t.direct, t.unmapped})
    for (int c = 0; c < 3; ++c) a[c] = r.get<int64_t>();
  t.casts = r.get<uint64_t>(), t.rays = r.get<uint64_t>(), t.emitter_hits = r.get<uint64_t>();
  return t;
}

std::vector<std::byte> encode(const Pass1Shard& shard) {
  Writer w;
  w.put_bytes(kMagic);
  w.put(kVersion);
  w.put(uint32_t(shard.atlas_width)), w.put(uint32_t(shard.atlas_height));
  put_tally(w, shard.sums.tally);
  const Pass1Sums& s = shard.sums;
  auto lit = [&](size_t k) {
    return s.node_weight[k] != 0 || s.node_power[3 * k] != 0 || s.node_power[3 * k + 1] != 0 ||
           s.node_power[3 * k + 2] != 0;
  };
  uint64_t n = 0;
  for (size_t k = 0; k < s.nodes(); ++k) n += lit(k);
  w.put(n);
  for (size_t k = 0; k < s.nodes(); ++k)
    if (lit(k)) {
      w.put(uint64_t(k));
      for (int c = 0; c < 3; ++c) w.put(s.node_power[3 * k + size_t(c)]);
      w.put(s.node_weight[k]);
    }
  return w.bytes();
}

}  // namespace

std::string pass1_shard_report_path(const std::string& data_path) {
  return std::filesystem::path(data_path).replace_extension(".json").string();
}

bool is_pass1_shard_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char magic[8] = {};
  return in.read(magic, 8) && std::string(magic, 8) == kMagic;
}

void write_pass1_shard(const std::string& data_path, const Scene& scene, const BakeParams& params,
                       int index, int count, const Pass1Shard& shard, double seconds) {
  const std::vector<std::byte> bytes = encode(shard);
  write_file_atomic(data_path, bytes);
  const json report = {
      {"format", "lightbake-pass1-shard"},
      {"version", kVersion},
      {"generator", "lightbake"},
      {"scene", scene.source_path},
      {"scene_hash", scene_hash(scene)},
      {"seed", params.seed},
      {"settings", bake_settings_json(params)},
      {"shard", {{"index", index}, {"count", count}}},
      {"atlas", {{"width", shard.atlas_width}, {"height", shard.atlas_height}}},
      {"data",
       {{"file", std::filesystem::path(data_path).filename().string()},
        {"bytes", bytes.size()},
        {"fnv1a", fnv1a_hex(bytes)}}},
      {"rays", shard.sums.tally.rays},
      {"seconds", seconds},
  };
  write_text_atomic(pass1_shard_report_path(data_path), json_text(report, 2) + "\n");
}

Pass1ShardReport read_pass1_shard_report(const std::string& data_path) {
  Pass1ShardReport shard;
  shard.data_path = data_path;
  shard.report_path = pass1_shard_report_path(data_path);
  std::ifstream in(shard.report_path);
  if (!in)
    throw std::runtime_error(shard.report_path +
                             ": cannot read the shard's report (written "
                             "beside its data)");
  try {
    shard.report = json::parse(in);
    if (shard.report.at("format") != "lightbake-pass1-shard") throw std::invalid_argument("");
    if (shard.report.at("version").get<uint32_t>() != kVersion)
      throw std::runtime_error(shard.report_path + ": a pass-1 shard of version " +
                               shard.report.at("version").dump() + "; this lightbake reads " +
                               std::to_string(kVersion));
    shard.index = shard.report.at("shard").at("index").get<int>();
    shard.count = shard.report.at("shard").at("count").get<int>();
    pass1_shard_shared(shard.report);  // every field present
  } catch (const std::runtime_error&) {
    throw;
  } catch (const std::exception&) {
    throw std::runtime_error(shard.report_path +
                             ": not the report of a `lightbake bake --shard` run");
  }
  return shard;
}

json pass1_shard_shared(const json& report) {
  return {{"scene_hash", report.at("scene_hash")},
          {"seed", report.at("seed")},
          {"settings", report.at("settings")},
          {"shard_count", report.at("shard").at("count")},
          {"atlas", report.at("atlas")}};
}

void add_pass1_shard_sums(const Pass1ShardReport& shard, Pass1Sums& sums) {
  const std::string& path = shard.data_path;
  Reader r(path);
  const json& data = shard.report.at("data");
  if (r.size() != data.value("bytes", uint64_t(0)) ||
      fnv1a_hex(r.bytes()) != data.value("fnv1a", std::string()))
    throw std::runtime_error(path + ": its size or FNV-1a differs from " + shard.report_path +
                             "'s: not the data that report describes");
  r.expect_magic(kMagic);
  if (r.get<uint32_t>() != kVersion) r.fail("unknown version");
  const uint32_t width = r.get<uint32_t>(), height = r.get<uint32_t>();
  if (uint64_t(width) * height != sums.nodes())
    r.fail("atlas " + std::to_string(width) + "x" + std::to_string(height) + " has " +
           std::to_string(uint64_t(width) * height) + " nodes, the bake's " +
           std::to_string(sums.nodes()));
  const FixedTally tally = get_tally(r);
  const uint64_t n = r.get<uint64_t>();
  if (n > sums.nodes()) r.fail("more nodes than the atlas has");
  try {
    uint64_t previous = 0;
    for (uint64_t i = 0; i < n; ++i) {
      const uint64_t node = r.get<uint64_t>();
      if (node >= sums.nodes() || (i > 0 && node <= previous)) r.fail("node index out of order");
      previous = node;
      for (int c = 0; c < 3; ++c)
        add_checked(sums.node_power[3 * node + size_t(c)], r.get<int64_t>(), "texel power");
      add_checked(sums.node_weight[node], r.get<int64_t>(), "deposit weights");
    }
    r.expect_end();
    sums.add_tally(tally);
  } catch (const illumination::FixedOverflow& e) {
    throw std::runtime_error(path + ": " + e.what());
  }
}

}  // namespace lb
