// `lightbake merge SHARD.exr... -o OUT.exr|png`: joins the shards of one render
// (`lightbake render --shard i/n`) into the whole image. Every pixel comes from the one shard
// that rendered its tile, so the result has the bits of the unsharded render. Shards of another
// scene, bake, settings or count, a missing or a repeated shard are refused, naming the file.
// `lightbake merge PART.pass1... -o BAKE`: the shards of a bake's pass 1 (app/merge_bake.h).
// `lightbake merge PART.refshard... -o ref.exr`: a reference render's (app/reference_shard.h).
// `lightbake merge PART.texshard... -o out.glb`: an export's direct light (app/export_shard.h).

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "app/commands.h"
#include "app/export_shard.h"
#include "app/merge_bake.h"
#include "app/output_path.h"
#include "app/radiance_output.h"
#include "app/reference_shard.h"
#include "app/shard_set.h"
#include "app/thread_option.h"
#include "bake/hq/hq_render.h"
#include "bake/io/atomic_file.h"
#include "bake/io/image_io.h"
#include "bake/json_text.h"
#include "bake/pipeline/pass1_shard_io.h"

namespace lb::app {

namespace {

struct MergeOptions {
  std::vector<std::string> shards;
  std::string output;  // default: render.exr for render shards, bake for pass-1 shards
  std::string scene;   // pass-1 and export shards: the scene, if not where they recorded it
  std::string bake;    // export shards: the bake, if not where they recorded it
  bool force = false;
  bool quiet = false;
};

struct Shard {
  std::string path;
  nlohmann::json report;
  int index = 0;
};

Shard read_shard(const std::string& path) {
  Shard shard{path, {}, 0};
  const std::string report_path = shard_report_path(path);
  std::ifstream in(report_path);
  if (!in) fail(report_path + ": cannot read the shard's report (written beside its image)");
  try {
    shard.report = nlohmann::json::parse(in);
    shard.index = shard.report.at("shard").at("index").get<int>();
  } catch (const std::exception&) {
    fail(report_path + ": not the report of a `lightbake render --shard` run");
  }
  return shard;
}

// The settings every shard of one render shares: everything but the shard's own index, what it
// measured and the paths (nodes may mount the scene elsewhere; its hash and the bake's say
// whether they are the same).
nlohmann::json shared_settings(const nlohmann::json& report) {
  nlohmann::json settings;
  for (const char* key : {"camera", "width", "height", "samples_per_side", "passes", "seed",
                          "max_depth", "final_gather", "terms", "scene_hash", "bake_hash", "tone"})
    settings[key] = report.value(key, nlohmann::json());
  settings["shard_count"] = report.at("shard").at("count");
  settings["tile_size"] = report.at("shard").at("tile_size");
  return settings;
}

// True if the shards are of the kind `extension` names; fail()s if only some are.
bool shards_of_kind(const std::vector<std::string>& shards, const std::string& extension) {
  size_t count = 0;
  for (const std::string& path : shards) count += lowercase_extension(path) == extension;
  if (count > 0 && count != shards.size())
    fail("merge: give shards of one kind, not both (" + extension + " and others)");
  return count > 0;
}

void run_merge(MergeOptions options) {
  if (shards_of_kind(options.shards, kPass1ShardExtension)) {
    BakeMergeOptions bake;
    bake.shards = options.shards;
    if (!options.output.empty()) bake.output_dir = options.output;
    bake.scene_path = options.scene;
    bake.force = options.force;
    bake.quiet = options.quiet;
    return merge_bake_shards(bake);
  }
  if (shards_of_kind(options.shards, kTexelShardExtension)) {
    return merge_export_shards({options.shards,
                                options.output.empty() ? "export.glb" : options.output,
                                options.scene, options.bake, options.force, options.quiet});
  }
  if (!options.bake.empty()) fail("--bake: only for export shards (.texshard)");
  if (!options.scene.empty()) fail("--scene: only for pass-1 and export shards");
  if (shards_of_kind(options.shards, kReferenceShardExtension)) {
    return merge_reference_shards(
        {options.shards, options.output.empty() ? "reference.exr" : options.output, options.force});
  }
  if (options.output.empty()) options.output = "render.exr";
  const std::string report_path = prepare_merged_image(options.output, options.force);

  std::vector<Shard> shards;
  for (const std::string& path : options.shards) shards.push_back(read_shard(path));
  const nlohmann::json settings = shared_settings(shards.front().report);
  const int count = settings["shard_count"].get<int>();
  const int width = settings["width"].get<int>(), height = settings["height"].get<int>();
  const int tile_size = settings["tile_size"].get<int>();
  if (count < 1 || count > kMaxShards || width < 1 || height < 1 || tile_size < 1 ||
      width > 16384 || height > 16384)
    fail(shard_report_path(shards.front().path) + ": shard settings out of range");
  std::vector<std::string> paths;
  std::vector<int> indices;
  for (const Shard& shard : shards) {
    const nlohmann::json mine = shared_settings(shard.report);
    for (auto it = settings.begin(); it != settings.end(); ++it)
      if (mine[it.key()] != it.value())
        fail(shard.path + ": " + it.key() + " " + mine[it.key()].dump() + " differs from " +
             shards.front().path + "'s " + it.value().dump() + ": not a shard of the same render");
    paths.push_back(shard.path);
    indices.push_back(shard.index);
  }
  const std::vector<size_t> by_index = shards_by_index(paths, indices, count);

  std::vector<vec3> pixels(size_t(width) * size_t(height), vec3(0.0f));
  for (int i = 0; i < count; ++i) {
    const Shard& shard = shards[by_index[size_t(i)]];
    const Image image =
        read_reported_image(shard.path, shard.report, shard_report_path(shard.path));
    if (image.width != width || image.height != height || image.channels < 3)
      fail(shard.path + ": image is " + std::to_string(image.width) + "x" +
           std::to_string(image.height) + ", its report says " + std::to_string(width) + "x" +
           std::to_string(height));
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        if (hq_shard_of_tile(hq_tile_of_pixel(x, y, width, tile_size), count) != i) continue;
        const size_t p = size_t(y) * size_t(width) + size_t(x);
        const float* v = &image.pixels[p * size_t(image.channels)];
        pixels[p] = vec3(v[0], v[1], v[2]);
      }
  }
  ToneMap tone;
  tone.curve = parse_tone_curve(settings["tone"].value("curve", "aces"));
  tone.exposure = settings["tone"].value("exposure", 0.0f);
  nlohmann::json report = settings;
  report["generator"] = "lightbake";
  report["output"] = options.output;
  report["merged_from"] = options.shards;
  double seconds = 0.0;
  uint64_t rays = 0;
  for (const Shard& shard : shards) {
    seconds += shard.report.value("render_seconds", 0.0);
    rays += shard.report.value("rays", nlohmann::json::object()).value("total", uint64_t{0});
  }
  report["render_seconds_summed"] = seconds;
  report["rays_summed"] = rays;
  write_radiance_image_and_report(options.output, pixels, width, height, tone, report_path,
                                  std::move(report));
  std::printf("merged     %d shards into %s (%dx%d), %s\n", count, options.output.c_str(), width,
              height, report_path.c_str());
}

}  // namespace

void register_merge(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "merge",
      "Join the shards of a render or a reference (render|reference --shard i/n) into the whole "
      "image, the pass-1 shards of a bake (bake --shard i/n) into the bake, or an export's "
      "(export --shard i/n) into the glTF");
  auto options = std::make_shared<MergeOptions>();
  cmd->add_option("shards", options->shards,
                  "The shards: .exr images, .pass1 sums, .refshard reference sums or .texshard "
                  "export texels (their .json beside them)")
      ->required();
  cmd->add_option("-o,--output", options->output,
                  "Image to write (.exr linear, .png tone mapped; default render.exr, "
                  "reference.exr for reference shards; .glb or .gltf for export shards, default "
                  "export.glb), or for pass-1 shards the bake directory (default bake)");
  cmd->add_option("--scene", options->scene,
                  "Pass-1 and export shards: the scene file, if not at the path they recorded "
                  "(its hash must match)");
  cmd->add_option("--bake", options->bake,
                  "Export shards: the bake directory, if not where they recorded it (its hash "
                  "must match)");
  cmd->add_flag("--force", options->force,
                "Replace the image or its .json report even if lightbake did not write them; "
                "write a bake into a folder that holds no bake");
  cmd->add_flag("-q,--quiet", options->quiet, "Pass-1 and export shards: no progress lines");
  add_threads_option(*cmd);
  cmd->callback([options] { run_merge(*options); });
}

}  // namespace lb::app
