#include "bake/hq/render_shards.h"

#include <stdexcept>

#include "bake/binary_file.h"
#include "bake/hq/hq_render.h"

namespace lb {

namespace {

using nlohmann::json;

[[noreturn]] void fail(const std::string& message) { throw std::runtime_error(message); }

// The positions (y * width + x) of the pixels shard `shard` of `count` renders, in row order:
// the order of its payload.
std::vector<size_t> shard_pixels(int width, int height, int tile_size, int shard, int count) {
  std::vector<size_t> owned;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      if (hq_shard_of_tile(hq_tile_of_pixel(x, y, width, tile_size), count) == shard)
        owned.push_back(size_t(y) * size_t(width) + size_t(x));
  return owned;
}

}  // namespace

json render_shard_settings(const json& render_report, int tile_size) {
  json settings;
  for (const char* key : {"camera", "width", "height", "samples_per_side", "passes", "seed",
                          "max_depth", "final_gather", "terms", "scene_hash", "bake_hash", "tone"})
    settings[key] = render_report.at(key);
  settings["tile_size"] = tile_size;
  return settings;
}

void write_render_shard(const std::string& data_path, const std::string& scene_path,
                        const std::string& bake_dir, const json& settings, int index, int count,
                        const std::vector<vec3>& pixels, const json& render_report) {
  Writer w;
  for (size_t p : shard_pixels(settings.at("width").get<int>(), settings.at("height").get<int>(),
                               settings.at("tile_size").get<int>(), index, count))
    w.put(pixels[p].x), w.put(pixels[p].y), w.put(pixels[p].z);
  shards::write_shard(data_path, kRenderShard, index, count, w.bytes(), scene_path, settings,
                      {{"bake", bake_dir},
                       {"rays", render_report.at("rays")},
                       {"render_seconds", render_report.at("render_seconds")},
                       {"bake_seconds", render_report.at("bake_seconds")}});
}

MergedRender merge_render_shards(const std::vector<std::string>& paths) {
  const std::vector<shards::ShardFile> set = shards::read_shard_set(paths, kRenderShard);
  const shards::ShardFile& first = set.front();
  int width = 0, height = 0, tile_size = 0;
  try {
    width = first.settings().at("width").get<int>();
    height = first.settings().at("height").get<int>();
    tile_size = first.settings().at("tile_size").get<int>();
    first.settings().at("tone").get<json::object_t>();
  } catch (const std::exception&) {
    fail(first.report_path + ": shard settings missing");
  }
  if (first.count > kMaxShards || width < 1 || height < 1 || tile_size < 1 || width > 16384 ||
      height > 16384)
    fail(first.report_path + ": shard settings out of range");

  MergedRender merged{std::vector<vec3>(size_t(width) * size_t(height), vec3(0.0f)), width,
                      height, first.settings()};
  double seconds = 0.0;
  uint64_t rays = 0;
  for (int i = 0; i < first.count; ++i) {
    const shards::ShardFile& shard = set[size_t(i)];
    Reader r = shards::open_shard_payload(shard, kRenderShard);
    for (size_t p : shard_pixels(width, height, tile_size, i, first.count))
      for (int c = 0; c < 3; ++c) merged.pixels[p][c] = r.get<float>();
    r.expect_end();
    seconds += shard.report.value("render_seconds", 0.0);
    rays += shard.report.value("rays", json::object()).value("total", uint64_t{0});
  }
  merged.report["generator"] = "lightbake";
  merged.report["merged_from"] = paths;
  merged.report["render_seconds_summed"] = seconds;
  merged.report["rays_summed"] = rays;
  return merged;
}

}  // namespace lb
