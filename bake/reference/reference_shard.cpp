#include "bake/reference/reference_shard.h"

#include <algorithm>
#include <stdexcept>

#include "bake/binary_file.h"
#include "bake/reference/film_io.h"

namespace lb::reference {

namespace {

using nlohmann::json;

[[noreturn]] void fail(const std::string& message) { throw std::runtime_error(message); }

json rays_json(const ReferenceRays& r) {
  return {{"camera", r.camera},           {"bounce", r.bounce},
          {"shadow", r.shadow},           {"light", r.light},
          {"connection", r.connection},   {"eye_paths", r.eye_paths},
          {"light_paths", r.light_paths}, {"cut_at_max_depth", r.cut_at_max_depth}};
}

ReferenceRays rays_from(const json& j) {
  ReferenceRays r;
  r.camera = j.at("camera"), r.bounce = j.at("bounce"), r.shadow = j.at("shadow");
  r.light = j.at("light"), r.connection = j.at("connection"), r.eye_paths = j.at("eye_paths");
  r.light_paths = j.at("light_paths"), r.cut_at_max_depth = j.at("cut_at_max_depth");
  return r;
}

ReferenceParams params_from(const json& settings) {
  ReferenceParams p;
  p.width = settings.at("width"), p.height = settings.at("height"), p.spp = settings.at("spp");
  p.seed = settings.at("seed");
  p.terms = settings.at("terms") == "direct" ? Terms::direct : Terms::all;
  p.light_paths_per_pixel = settings.at("light_paths_per_pixel");
  p.light_tracing = settings.at("light_tracing");
  p.roulette_threshold = settings.at("roulette_threshold");
  p.max_depth = settings.at("max_depth");
  p.tile_size = settings.at("tile_size");
  p.light_block_size = settings.at("light_block_size");
  const json& w = settings.at("window");
  p.window = {w.at(0), w.at(1), w.at(2), w.at(3)};
  return p;
}

}  // namespace

json reference_shard_settings(const std::string& scene_hash, const std::string& camera,
                              const ReferenceParams& p, const std::string& tone_curve,
                              float exposure) {
  return {{"scene_hash", scene_hash},
          {"camera", camera},
          {"width", p.width},
          {"height", p.height},
          {"spp", p.spp},
          {"seed", p.seed},
          {"terms", p.terms == Terms::all ? "all" : "direct"},
          {"light_paths_per_pixel", p.light_paths_per_pixel},
          {"light_tracing", p.light_tracing},
          {"roulette_threshold", p.roulette_threshold},
          {"max_depth", p.max_depth},
          {"tile_size", p.tile_size},
          {"light_block_size", p.light_block_size},
          {"tone", {{"curve", tone_curve}, {"exposure", exposure}}},
          {"window", {p.window.x, p.window.y, p.window.width, p.window.height}}};
}

void write_reference_shard(const std::string& data_path, const std::string& scene_path,
                           const json& settings, const ReferenceParams& params, const Film& film,
                           const ReferenceStats& stats) {
  shards::write_shard(data_path, kReferenceShard, params.shard, params.shard_count,
                      encode_film(film), scene_path, settings,
                      {{"passes", film.passes()},
                       {"rays", rays_json(stats.rays)},
                       {"cpu_seconds", stats.cpu_seconds},
                       {"wall_seconds", stats.wall_seconds}});
}

MergedReference merge_reference_shards(const std::vector<std::string>& paths) {
  const std::vector<shards::ShardFile> set = shards::read_shard_set(paths, kReferenceShard);
  const shards::ShardFile& first = set.front();
  MergedReference merged;
  merged.settings = first.settings();
  merged.scene_path = first.report.value("scene", std::string());
  merged.report_path = first.report_path;
  merged.shard_count = first.count;
  ReferenceParams& params = merged.params;
  try {
    params = params_from(merged.settings);
    params.shard_count = first.count;
    check_reference_params(params);
    merged.settings.at("camera").get<std::string>();
  } catch (const std::exception&) {
    fail(first.report_path + ": settings out of range");
  }

  const PixelWindow window = render_window(params);
  merged.film = Film(window.width, window.height);
  for (int i = 0; i < first.count; ++i) {
    const shards::ShardFile& shard = set[size_t(i)];
    Reader r = shards::open_shard_payload(shard, kReferenceShard);
    const Film part = decode_film(r);
    params.shard = i;
    // Exactly its own passes: pass k belongs to shard k mod count.
    bool own = part.width == window.width && part.height == window.height &&
               part.passes() == shard_passes(params);
    for (size_t k = 0; own && k < part.pass_indices.size(); ++k)
      own = part.pass_indices[k] == uint64_t(i) + uint64_t(k) * uint64_t(first.count);
    if (!own)
      fail(shard.data_path + ": does not hold the passes of shard " + std::to_string(i) + " of " +
           std::to_string(first.count) + " of a " + std::to_string(params.width) + "x" +
           std::to_string(params.height) + ", " + std::to_string(params.spp) + "-pass render");
    merged.film.add(part);
    try {
      merged.stats.rays += rays_from(shard.report.at("rays"));
      merged.stats.cpu_seconds += shard.report.at("cpu_seconds").get<double>();
      merged.stats.wall_seconds =
          std::max(merged.stats.wall_seconds, shard.report.at("wall_seconds").get<double>());
    } catch (const std::exception&) {
      fail(shard.report_path + ": rays or seconds missing");
    }
  }
  params.shard = 0;
  params.shard_count = 1;
  return merged;
}

}  // namespace lb::reference
