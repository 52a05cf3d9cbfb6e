#include "bake/hq/render_shards.h"

#include <fstream>
#include <stdexcept>

#include "bake/binary_file.h"
#include "bake/hq/hq_render.h"
#include "bake/shards/shard_file.h"

namespace lb {

namespace {

using nlohmann::json;

[[noreturn]] void fail(const std::string& message) { throw std::runtime_error(message); }

struct RenderShard {
  std::string path;
  json report;
  int index = 0;
};

RenderShard read_render_shard(const std::string& path) {
  RenderShard shard{path, {}, 0};
  const std::string report_path = shards::shard_report_path(path);
  std::ifstream in(report_path);
  if (!in) fail(report_path + ": cannot read the shard's report (written beside its image)");
  try {
    shard.report = json::parse(in);
    shard.index = shard.report.at("shard").at("index").get<int>();
  } catch (const std::exception&) {
    fail(report_path + ": not the report of a `lightbake render --shard` run");
  }
  return shard;
}

// The settings every shard of one render shares: everything but the shard's own index, what it
// measured and the paths (nodes may mount the scene elsewhere; its hash and the bake's say
// whether they are the same).
json shared_settings(const json& report) {
  json settings;
  for (const char* key : {"camera", "width", "height", "samples_per_side", "passes", "seed",
                          "max_depth", "final_gather", "terms", "scene_hash", "bake_hash", "tone"})
    settings[key] = report.value(key, json());
  settings["shard_count"] = report.at("shard").at("count");
  settings["tile_size"] = report.at("shard").at("tile_size");
  return settings;
}

// The shard's image, if its bytes are the ones its report records (not one run's image with
// another's report).
Image read_reported_image(const RenderShard& shard) {
  const Reader file(shard.path);
  const json recorded = shard.report.value("image", json());
  if (recorded.is_object() && recorded.value("fnv1a", std::string()) != fnv1a_hex(file.bytes()))
    fail(shard.path + ": its FNV-1a " + fnv1a_hex(file.bytes()) + " is not the " +
         recorded.value("fnv1a", json()).dump() + " that " + shards::shard_report_path(shard.path) +
         " records: the image and the report are of different runs; render again");
  return read_image(shard.path, file.bytes());
}

}  // namespace

MergedRender merge_render_shards(const std::vector<std::string>& paths) {
  std::vector<RenderShard> set;
  for (const std::string& path : paths) set.push_back(read_render_shard(path));
  const json settings = shared_settings(set.front().report);
  const int count = settings["shard_count"].get<int>();
  const int width = settings["width"].get<int>(), height = settings["height"].get<int>();
  const int tile_size = settings["tile_size"].get<int>();
  if (count < 1 || count > kMaxShards || width < 1 || height < 1 || tile_size < 1 ||
      width > 16384 || height > 16384)
    fail(shards::shard_report_path(set.front().path) + ": shard settings out of range");
  std::vector<int> indices;
  for (const RenderShard& shard : set) {
    shards::check_same_settings(shared_settings(shard.report), settings, shard.path,
                                set.front().path, "render");
    indices.push_back(shard.index);
  }
  const std::vector<size_t> by_index = shards::shards_by_index(paths, indices, count);

  MergedRender merged{std::vector<vec3>(size_t(width) * size_t(height), vec3(0.0f)), width,
                      height, {}, settings};
  for (int i = 0; i < count; ++i) {
    const RenderShard& shard = set[by_index[size_t(i)]];
    const Image image = read_reported_image(shard);
    if (image.width != width || image.height != height || image.channels < 3)
      fail(shard.path + ": image is " + std::to_string(image.width) + "x" +
           std::to_string(image.height) + ", its report says " + std::to_string(width) + "x" +
           std::to_string(height));
    copy_shard_tiles(image.pixels, image.channels, width, height, tile_size, i, count,
                     merged.pixels);
  }
  merged.tone.curve = parse_tone_curve(settings["tone"].value("curve", "aces"));
  merged.tone.exposure = settings["tone"].value("exposure", 0.0f);
  merged.report["generator"] = "lightbake";
  merged.report["merged_from"] = paths;
  double seconds = 0.0;
  uint64_t rays = 0;
  for (const RenderShard& shard : set) {
    seconds += shard.report.value("render_seconds", 0.0);
    rays += shard.report.value("rays", json::object()).value("total", uint64_t{0});
  }
  merged.report["render_seconds_summed"] = seconds;
  merged.report["rays_summed"] = rays;
  return merged;
}

}  // namespace lb
