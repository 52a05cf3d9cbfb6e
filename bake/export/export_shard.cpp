#include "bake/export/export_shard.h"

#include <filesystem>
#include <stdexcept>

#include "bake/binary_file.h"

namespace lb {

namespace {

using nlohmann::json;

[[noreturn]] void fail(const std::string& message) { throw std::runtime_error(message); }

vec3 get_vec3(const std::vector<float>& values, size_t i) {
  return vec3(values[i * 3], values[i * 3 + 1], values[i * 3 + 2]);
}

// The shard's rows into `band` (width x height; l1 and filled when directional, unshadowed when
// `unshadowed`); returns them.
TexelRows read_shard_rows(const shards::ShardFile& shard, bool directional, bool unshadowed,
                          DirectBand& band) {
  const int width = band.width, height = band.height;
  Reader r = shards::open_shard_payload(shard, kExportShard);
  const uint32_t begin = r.get<uint32_t>(), end = r.get<uint32_t>();
  if (begin > end || end > uint32_t(height)) r.fail("rows out of the atlas");
  const TexelRows rows{int(begin), int(end)};
  for (int j = rows.begin; j < rows.end; ++j) {
    const size_t first = size_t(j) * size_t(width);
    const std::vector<float> row = r.get_array<float>(size_t(width) * 3);
    for (size_t i = 0; i < size_t(width); ++i) band.l0[first + i] = get_vec3(row, i);
    if (unshadowed) {
      const std::vector<float> sampled = r.get_array<float>(size_t(width) * 3);
      for (size_t i = 0; i < size_t(width); ++i) band.unshadowed[first + i] = get_vec3(sampled, i);
    }
    if (!directional) continue;
    const std::vector<float> l1 = r.get_array<float>(size_t(width) * 9);
    const std::vector<uint8_t> filled = r.get_array<uint8_t>(size_t(width));
    for (size_t i = 0; i < size_t(width); ++i) {
      for (size_t a = 0; a < 3; ++a) band.l1[a][first + i] = get_vec3(l1, i * 3 + a);
      if (filled[i] > 1) r.fail("a node's surface flag is not 0 or 1");
      band.filled[first + i] = filled[i];
    }
  }
  r.expect_end();
  return rows;
}

void put_vec3(Writer& w, vec3 v) { w.put(v.x), w.put(v.y), w.put(v.z); }

// The rows' payload: `put_row(w, j)` puts node row j's data after the rows.
template <class PutRow>
std::vector<std::byte> rows_payload(TexelRows rows, const PutRow& put_row) {
  Writer w;
  w.put(uint32_t(rows.begin)), w.put(uint32_t(rows.end));
  for (int j = rows.begin; j < rows.end; ++j) put_row(w, j);
  return w.bytes();
}

void write_rows_shard(const std::string& data_path, const ExportShardSource& source, int width,
                      int height, TexelRows rows, const std::vector<std::byte>& payload,
                      bool unshadowed, uint64_t shadow_rays, uint64_t points, int index,
                      int count, double seconds) {
  const json settings = {{"scene_hash", source.scene_hash},
                         {"bake_hash", source.bake_hash},
                         {"contents", "all"},
                         {"direct_samples", source.direct_side},
                         {"lightmap_format", source.lightmap_format},
                         {"lightmap_encoding", source.lightmap_encoding},
                         {"atlas_width", width},
                         {"atlas_height", height},
                         {"denoise", source.denoise},
                         {"directional", source.directional},
                         {"directional_share", source.directional_share},
                         {"shadow_side", source.shadow_side},
                         {"unshadowed", unshadowed}};
  shards::write_shard(
      data_path, kExportShard, index, count, payload, source.scene_path, settings,
      {{"bake", source.bake_dir},
       {"rows", {{"begin", rows.begin}, {"end", rows.end}}},  // node rows [begin, end)
       // Its rows' rays and the cell row above them, which the shard before also traces.
       {"shadow_rays", shadow_rays},
       // The points estimated, the work the rows were split by (those facing no light trace
       // no shadow ray).
       {"points", points},
       {"seconds", seconds}});
}

}  // namespace

void write_export_shard(const std::string& data_path, const ExportShardSource& source,
                        const Lightmap& lightmap, int index, int count, double seconds) {
  if (source.directional) fail(data_path + ": a directional shard written without its band");
  const size_t width = size_t(lightmap.width);
  const bool unshadowed = !lightmap.direct_unshadowed.empty();
  const auto payload = rows_payload(lightmap.direct_rows, [&](Writer& w, int j) {
    for (size_t i = 0; i < width; ++i) put_vec3(w, lightmap.direct[size_t(j) * width + i]);
    if (unshadowed)
      for (size_t i = 0; i < width; ++i)
        put_vec3(w, lightmap.direct_unshadowed[size_t(j) * width + i]);
  });
  write_rows_shard(data_path, source, lightmap.width, lightmap.height, lightmap.direct_rows,
                   payload, unshadowed, lightmap.shadow_rays, lightmap.direct_points, index,
                   count, seconds);
}

void write_export_shard(const std::string& data_path, const ExportShardSource& source,
                        const DirectBand& band, int index, int count, double seconds) {
  if (!source.directional) fail(data_path + ": a direct band written as a plain shard");
  const size_t width = size_t(band.width);
  const bool unshadowed = !band.unshadowed.empty();
  const auto payload = rows_payload(band.rows, [&](Writer& w, int j) {
    const size_t first = size_t(j) * width;
    for (size_t i = 0; i < width; ++i) put_vec3(w, band.l0[first + i]);
    if (unshadowed)
      for (size_t i = 0; i < width; ++i) put_vec3(w, band.unshadowed[first + i]);
    for (size_t i = 0; i < width; ++i)
      for (size_t a = 0; a < 3; ++a) put_vec3(w, band.l1[a][first + i]);
    for (size_t i = 0; i < width; ++i) w.put(band.filled[first + i]);
  });
  write_rows_shard(data_path, source, band.width, band.height, band.rows, payload, unshadowed,
                   band.shadow_rays, band.points, index, count, seconds);
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
    set.gltf.directional = settings.value("directional", false);
    set.gltf.directional_share = settings.value("directional_share", false);
    set.gltf.shadow_side = settings.value("shadow_side", 0);
    set.unshadowed = settings.value("unshadowed", false);
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

DirectBand join_export_shards(const ExportShardSet& set) {
  DirectBand band;
  band.width = set.width;
  band.height = set.height;
  band.rows = {0, set.height};
  const size_t texels = size_t(set.width) * size_t(set.height);
  band.l0.assign(texels, vec3(0.0f));
  const bool directional = set.gltf.directional;
  if (directional) {
    for (auto& axis : band.l1) axis.assign(texels, vec3(0.0f));
    band.filled.assign(texels, 0);
  }
  if (set.unshadowed) band.unshadowed.assign(texels, vec3(0.0f));
  // Shard i's rows follow shard i - 1's; the last ends at the atlas's last row.
  int next_row = 0;
  for (size_t i = 0; i < set.shards.size(); ++i) {
    const shards::ShardFile& shard = set.shards[i];
    const TexelRows rows = read_shard_rows(shard, directional, set.unshadowed, band);
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
  return band;
}

}  // namespace lb
