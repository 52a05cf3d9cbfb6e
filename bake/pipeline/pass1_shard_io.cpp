#include "bake/pipeline/pass1_shard_io.h"

#include <algorithm>
#include <stdexcept>

#include "bake/binary_file.h"
#include "bake/light_groups.h"
#include "bake/pipeline/bake_io.h"

namespace lb {

namespace {

using illumination::add_checked;
using illumination::FixedTally;
using illumination::Pass1Sums;
using nlohmann::json;

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
  w.put(uint32_t(shard.atlas_width)), w.put(uint32_t(shard.atlas_height));
  put_tally(w, shard.sums.tally);
  const Pass1Sums& s = shard.sums;
  auto group_lit = [&](size_t k) {
    for (size_t g = 0; g < s.groups(); ++g)
      for (int c = 0; c < 3; ++c)
        if (s.group_power.at(g, k, c) != 0) return true;
    return false;
  };
  auto band_lit = [&](size_t k) {
    return !s.node_l1.empty() &&
           std::any_of(s.node_l1.begin() + std::ptrdiff_t(9 * k),
                       s.node_l1.begin() + std::ptrdiff_t(9 * k + 9),
                       [](int64_t v) { return v != 0; });
  };
  auto lit = [&](size_t k) {
    return s.node_weight[k] != 0 || s.node_power[3 * k] != 0 || s.node_power[3 * k + 1] != 0 ||
           s.node_power[3 * k + 2] != 0 || group_lit(k) || band_lit(k);
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
  // Light groups: their count, then each listed node's power per group (a scene without groups
  // writes nothing here: its shards keep their bytes).
  if (s.groups() > 0) {
    w.put(uint32_t(s.groups()));
    for (size_t k = 0; k < s.nodes(); ++k)
      if (lit(k))
        for (size_t g = 0; g < s.groups(); ++g)
          for (int c = 0; c < 3; ++c) w.put(s.group_power.at(g, k, c));
  }
  // Directional bakes: each listed node's L1 sums (9, as Pass1Sums::node_l1); the merge knows
  // to read them from the settings the shards record.
  if (!s.node_l1.empty())
    for (size_t k = 0; k < s.nodes(); ++k)
      if (lit(k))
        for (size_t i = 0; i < 9; ++i) w.put(s.node_l1[9 * k + i]);
  return w.bytes();
}

// Adds the shard's sums into `sums`.
void add_shard_sums(const shards::ShardFile& shard, Pass1Sums& sums) {
  Reader r = shards::open_shard_payload(shard, kPass1Shard);
  const uint32_t width = r.get<uint32_t>(), height = r.get<uint32_t>();
  if (uint64_t(width) * height != sums.nodes())
    r.fail("atlas " + std::to_string(width) + "x" + std::to_string(height) + " has " +
           std::to_string(uint64_t(width) * height) + " nodes, the bake's " +
           std::to_string(sums.nodes()));
  const FixedTally tally = get_tally(r);
  const uint64_t n = r.get<uint64_t>();
  if (n > sums.nodes()) r.fail("more nodes than the atlas has");
  try {
    std::vector<uint64_t> nodes(n);
    for (uint64_t i = 0; i < n; ++i) {
      const uint64_t node = r.get<uint64_t>();
      if (node >= sums.nodes() || (i > 0 && node <= nodes[i - 1]))
        r.fail("node index out of order");
      nodes[i] = node;
      for (int c = 0; c < 3; ++c)
        add_checked(sums.node_power[3 * node + size_t(c)], r.get<int64_t>(), "texel power");
      add_checked(sums.node_weight[node], r.get<int64_t>(), "deposit weights");
    }
    const uint32_t groups = sums.groups() > 0 ? r.get<uint32_t>() : 0;
    if (groups != sums.groups())
      r.fail(std::to_string(groups) + " light groups, the scene's " +
             std::to_string(sums.groups()));
    for (const uint64_t node : nodes)
      for (size_t g = 0; g < groups; ++g)
        for (int c = 0; c < 3; ++c) sums.group_power.add_atomic(g, node, c, r.get<int64_t>());
    if (!sums.node_l1.empty())
      for (const uint64_t node : nodes)
        for (size_t i = 0; i < 9; ++i)
          add_checked(sums.node_l1[9 * node + i], r.get<int64_t>(), "texel L1 power");
    r.expect_end();
    sums.add_tally(tally);
  } catch (const illumination::FixedOverflow& e) {
    throw std::runtime_error(shard.data_path + ": " + e.what());
  }
}

}  // namespace

void write_pass1_shard(const std::string& data_path, const Scene& scene, const BakeParams& params,
                       int index, int count, const Pass1Shard& shard, double seconds) {
  const json settings = {
      {"scene_hash", scene_hash(scene)},
      {"atlas", {{"width", shard.atlas_width}, {"height", shard.atlas_height}}},
      {"bake", bake_settings_json(params)}};
  shards::write_shard(data_path, kPass1Shard, index, count, encode(shard), scene.source_path,
                      settings, {{"rays", shard.sums.tally.rays}, {"seconds", seconds}});
}

Pass1ShardSet read_pass1_shard_set(const std::vector<std::string>& paths) {
  Pass1ShardSet set{shards::read_shard_set(paths, kPass1Shard), {}, {}};
  const shards::ShardFile& first = set.shards.front();
  set.scene_path = first.report.value("scene", std::string());
  try {
    first.settings().at("scene_hash").get<std::string>();
    first.settings().at("atlas").at("width").get<int>();
    first.settings().at("atlas").at("height").get<int>();
    first.settings().at("bake").get<json::object_t>();
  } catch (const std::exception&) {
    throw std::runtime_error(first.report_path +
                             ": not the report of a `lightbake bake --shard` run");
  }
  set.params = bake_settings_from_json(first.settings().at("bake"), first.report_path);
  return set;
}

BakeResult bake_from_pass1_shards(const Pass1ShardSet& set, const Scene& scene,
                                  const std::string& scene_path, const Progress& progress) {
  const shards::ShardFile& first = set.shards.front();
  shards::check_recorded_hash(first, "scene_hash", scene_path, scene_hash(scene), "scene", "baked");
  const json& atlas = first.settings().at("atlas");
  Pass1Sums sums(size_t(atlas.at("width").get<int>()) * size_t(atlas.at("height").get<int>()),
                 light_group_names(scene).size(), set.params.illumination.directional);
  for (const shards::ShardFile& shard : set.shards) add_shard_sums(shard, sums);
  return bake_from_pass1_sums(scene, set.params, sums, progress);
}

}  // namespace lb
