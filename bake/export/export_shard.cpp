#include "bake/export/export_shard.h"

#include <filesystem>
#include <stdexcept>

#include "bake/binary_file.h"

namespace lb {

namespace {

using nlohmann::json;

[[noreturn]] void fail(const std::string& message) { throw std::runtime_error(message); }

// The shard's rows into `direct` (width x height); returns them.
TexelRows read_shard_rows(const shards::ShardFile& shard, int width, int height,
                          std::vector<vec3>& direct) {
  Reader r = shards::open_shard_payload(shard, kExportShard);
  const uint32_t begin = r.get<uint32_t>(), end = r.get<uint32_t>();
  if (begin > end || end > uint32_t(height)) r.fail("rows out of the atlas");
  const TexelRows rows{int(begin), int(end)};
  for (int j = rows.begin; j < rows.end; ++j) {
    const std::vector<float> row = r.get_array<float>(size_t(width) * 3);
    for (int i = 0; i < width; ++i)
      direct[size_t(j) * size_t(width) + size_t(i)] =
          vec3(row[size_t(i) * 3], row[size_t(i) * 3 + 1], row[size_t(i) * 3 + 2]);
  }
  r.expect_end();
  return rows;
}

}  // namespace

void write_export_shard(const std::string& data_path, const ExportShardSource& source,
                        const Lightmap& lightmap, int index, int count, double seconds) {
  Writer w;
  const TexelRows rows = lightmap.direct_rows;
  w.put(uint32_t(rows.begin)), w.put(uint32_t(rows.end));
  for (int j = rows.begin; j < rows.end; ++j)
    for (int i = 0; i < lightmap.width; ++i) {
      const vec3 v = lightmap.direct[size_t(j) * size_t(lightmap.width) + size_t(i)];
      w.put(v.x), w.put(v.y), w.put(v.z);
    }
  const json settings = {{"scene_hash", source.scene_hash},
                         {"bake_hash", source.bake_hash},
                         {"contents", "all"},
                         {"direct_samples", source.direct_side},
                         {"lightmap_format", source.lightmap_format},
                         {"lightmap_encoding", source.lightmap_encoding},
                         {"atlas_width", lightmap.width},
                         {"atlas_height", lightmap.height},
                         {"denoise", source.denoise},
                         {"shadow_side", source.shadow_side}};
  shards::write_shard(
      data_path, kExportShard, index, count, w.bytes(), source.scene_path, settings,
      {{"bake", source.bake_dir},
       {"rows", {{"begin", rows.begin}, {"end", rows.end}}},  // node rows [begin, end)
       // Its rows' rays and the cell row above them, which the shard before also traces.
       {"shadow_rays", lightmap.shadow_rays},
       // The points estimated, the work the rows were split by (those facing no light trace
       // no shadow ray).
       {"points", lightmap.direct_points},
       {"seconds", seconds}});
}

ExportShardSet read_export_shard_set(const std::vector<std::string>& paths) {
  ExportShardSet set;
  set.shards = shards::read_shard_set(paths, kExportShard);
  const shards::ShardFile& first = set.shards.front();
  const json& settings = first.settings();
  set.gltf.contents = LightmapContents::all;
  try {
    set.gltf.format = parse_lightmap_format(settings.at("lightmap_format").get<std::string>());
    set.gltf.encoding =
        parse_lightmap_encoding(settings.at("lightmap_encoding").get<std::string>());
    set.gltf.direct_side = settings.at("direct_samples").get<int>();
    set.gltf.denoise_direct = settings.value("denoise", false);
    set.gltf.shadow_side = settings.value("shadow_side", 0);
    if (set.gltf.shadow_side < 0 || set.gltf.shadow_side > 64) throw std::invalid_argument("");
    set.width = settings.at("atlas_width").get<int>();
    set.height = settings.at("atlas_height").get<int>();
    if (set.width < 0 || set.height < 0 || set.width > 65536 || set.height > 65536)
      throw std::invalid_argument("");
  } catch (const std::exception&) {
    fail(first.report_path + ": settings out of range or of another lightbake");
  }
  set.scene_path = first.report.value("scene", std::string());
  set.bake_dir = first.report.value("bake", std::string());
  return set;
}

std::vector<vec3> join_export_shards(const ExportShardSet& set) {
  std::vector<vec3> direct(size_t(set.width) * size_t(set.height), vec3(0.0f));
  // Shard i's rows follow shard i - 1's; the last ends at the atlas's last row.
  int next_row = 0;
  for (size_t i = 0; i < set.shards.size(); ++i) {
    const shards::ShardFile& shard = set.shards[i];
    const TexelRows rows = read_shard_rows(shard, set.width, set.height, direct);
    if (rows.begin != next_row)
      fail(shard.data_path + ": its rows begin at " + std::to_string(rows.begin) + ", not at " +
           std::to_string(next_row) +
           (i > 0 ? " where shard " + std::to_string(i - 1) + "'s end" : std::string()) +
           ": not a shard of the same partition");
    next_row = rows.end;
  }
  if (next_row != set.height)
    fail(set.shards.back().data_path + ": the last shard's rows end at " +
         std::to_string(next_row) + ", not at the atlas's " + std::to_string(set.height));
  return direct;
}

}  // namespace lb
