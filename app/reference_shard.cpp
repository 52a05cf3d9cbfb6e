#include "app/reference_shard.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "app/commands.h"
#include "app/output_path.h"
#include "app/radiance_output.h"
#include "app/shard_set.h"
#include "bake/io/atomic_file.h"
#include "bake/json_text.h"
#include "bake/binary_file.h"
#include "bake/reference/film_io.h"
#include "bake/reference/report.h"

namespace lb::app {

namespace {

using nlohmann::json;
constexpr const char* kReferenceShardFormat = "lightbake-reference-shard";
constexpr uint32_t kReportVersion = 1;

json rays_json(const reference::ReferenceRays& r) {
  return {{"camera", r.camera},           {"bounce", r.bounce},
          {"shadow", r.shadow},           {"light", r.light},
          {"connection", r.connection},   {"eye_paths", r.eye_paths},
          {"light_paths", r.light_paths}, {"cut_at_max_depth", r.cut_at_max_depth}};
}

reference::ReferenceRays rays_from(const json& j) {
  reference::ReferenceRays r;
  r.camera = j.at("camera"), r.bounce = j.at("bounce"), r.shadow = j.at("shadow");
  r.light = j.at("light"), r.connection = j.at("connection"), r.eye_paths = j.at("eye_paths");
  r.light_paths = j.at("light_paths"), r.cut_at_max_depth = j.at("cut_at_max_depth");
  return r;
}

reference::Film read_shard_film(const ShardFile& shard) {
  Reader r = open_shard_data(shard);
  try {
    return reference::decode_film(r);
  } catch (const std::runtime_error& e) {
    fail(e.what());
  }
}

reference::ReferenceParams params_from(const json& settings) {
  reference::ReferenceParams p;
  p.width = settings.at("width"), p.height = settings.at("height"), p.spp = settings.at("spp");
  p.seed = settings.at("seed");
  p.terms = settings.at("terms") == "direct" ? reference::Terms::direct : reference::Terms::all;
  p.light_paths_per_pixel = settings.at("light_paths_per_pixel");
  p.light_tracing = settings.at("light_tracing");
  p.roulette_threshold = settings.at("roulette_threshold");
  p.max_depth = settings.at("max_depth");
  p.tile_size = settings.at("tile_size");
  p.light_block_size = settings.at("light_block_size");
  if (settings.contains("window")) {  // shards written before --window have none
    const json& w = settings.at("window");
    p.window = {w.at(0), w.at(1), w.at(2), w.at(3)};
  }
  return p;
}

}  // namespace

bool is_reference_shard_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char magic[8] = {};
  return in.read(magic, 8) && std::string(magic, 8) == reference::kFilmMagic;
}

json reference_shard_settings(const std::string& scene_hash, const std::string& camera,
                              const reference::ReferenceParams& p, const std::string& tone_curve,
                              float exposure) {
  return {{"scene_hash", scene_hash},
          {"camera", camera},
          {"width", p.width},
          {"height", p.height},
          {"spp", p.spp},
          {"seed", p.seed},
          {"terms", p.terms == reference::Terms::all ? "all" : "direct"},
          {"light_paths_per_pixel", p.light_paths_per_pixel},
          {"light_tracing", p.light_tracing},
          {"roulette_threshold", p.roulette_threshold},
          {"max_depth", p.max_depth},
          {"tile_size", p.tile_size},
          {"light_block_size", p.light_block_size},
          {"tone", {{"curve", tone_curve}, {"exposure", exposure}}},
          {"shard_count", p.shard_count},
          {"window", {p.window.x, p.window.y, p.window.width, p.window.height}}};
}

void write_reference_shard(const std::string& data_path, const std::string& scene_path,
                           const json& settings, const reference::ReferenceParams& params,
                           const reference::Film& film, const reference::ReferenceStats& stats) {
  const std::vector<std::byte> bytes = reference::encode_film(film);
  write_file_atomic(data_path, bytes);
  const json report = {
      {"format", kReferenceShardFormat},
      {"version", kReportVersion},
      {"generator", "lightbake"},
      {"scene", scene_path},
      {"settings", settings},
      {"shard", {{"index", params.shard}, {"count", params.shard_count}}},
      {"data",
       {{"file", std::filesystem::path(data_path).filename().string()},
        {"bytes", bytes.size()},
        {"fnv1a", fnv1a_hex(bytes)}}},
      {"passes", film.passes()},
      {"rays", rays_json(stats.rays)},
      {"cpu_seconds", stats.cpu_seconds},
      {"wall_seconds", stats.wall_seconds},
  };
  write_text_atomic(shard_report_path(data_path), json_text(report, 2) + "\n");
}

void merge_reference_shards(const ReferenceMergeOptions& options) {
  const std::string report_path = prepare_merged_image(options.output, options.force);

  std::vector<ShardFile> shards;
  for (const std::string& path : options.shards)
    shards.push_back(read_shard_file(path, kReferenceShardFormat, kReportVersion, "reference"));
  const std::vector<size_t> by_index = check_shard_files(shards, "render");
  const ShardFile& first = shards.front();
  const json& settings = first.report.at("settings");
  reference::ReferenceParams params;
  try {
    params = params_from(settings);
    params.shard_count = first.count;
    reference::check_reference_params(params);
  } catch (const std::exception&) {
    fail(first.report_path + ": settings out of range");
  }

  const reference::PixelWindow window = reference::render_window(params);
  reference::Film film(window.width, window.height);
  reference::ReferenceStats stats;
  for (int i = 0; i < first.count; ++i) {
    const ShardFile& shard = shards[by_index[size_t(i)]];
    const reference::Film part = read_shard_film(shard);
    params.shard = i;
    // Exactly its own passes: pass k belongs to shard k mod count.
    bool own = part.width == window.width && part.height == window.height &&
               part.passes() == reference::shard_passes(params);
    for (size_t k = 0; own && k < part.pass_indices.size(); ++k)
      own = part.pass_indices[k] == uint64_t(i) + uint64_t(k) * uint64_t(first.count);
    if (!own)
      fail(shard.data_path + ": does not hold the passes of shard " + std::to_string(i) + " of " +
           std::to_string(first.count) + " of a " + std::to_string(params.width) + "x" +
           std::to_string(params.height) + ", " + std::to_string(params.spp) + "-pass render");
    film.add(part);
    try {
      stats.rays += rays_from(shard.report.at("rays"));
      stats.cpu_seconds += shard.report.at("cpu_seconds").get<double>();
      stats.wall_seconds =
          std::max(stats.wall_seconds, shard.report.at("wall_seconds").get<double>());
    } catch (const std::exception&) {
      fail(shard.report_path + ": rays or seconds missing");
    }
  }
  params.shard = 0;
  params.shard_count = 1;

  ToneMap tone;
  try {
    tone.curve = parse_tone_curve(settings.at("tone").at("curve").get<std::string>());
    tone.exposure = settings.at("tone").at("exposure").get<float>();
  } catch (const std::exception&) {
    fail(first.report_path + ": tone settings missing or unknown");
  }
  const reference::ReportInfo info{first.report.value("scene", std::string()), options.output,
                                   settings.at("camera").get<std::string>()};
  json report = json::parse(reference::report_json(info, params, film, stats));
  report["merged_from"] = options.shards;
  report["shard_count"] = first.count;
  // Seconds over the shards: CPU summed, wall the longest shard's.
  write_radiance_image_and_report(options.output,
                                  reference::window_in_image(film.average(), params), params.width,
                                  params.height, tone, report_path, std::move(report));
  const reference::NoiseEstimate noise = film.noise();
  std::printf("merged     %d reference shards into %s (%dx%d, %d spp), %s\n", first.count,
              options.output.c_str(), params.width, params.height, film.passes(),
              report_path.c_str());
  std::printf("noise      %.2f%% per pixel (RMS), %.3f%% on the image mean\n",
              100.0 * noise.pixel_relative_standard_error,
              100.0 * noise.mean_relative_standard_error);
}

}  // namespace lb::app
