// `lightbake merge PART.rendershard... -o OUT.exr|png`: joins the shards of one render
// (`lightbake render --shard i/n`) into the whole image, with the unsharded render's bits
// (bake/hq/render_shards.h). `lightbake merge PART.pass1... -o BAKE`: the shards of a bake's pass 1
// (bake/pipeline/pass1_shard_io.h). `lightbake merge PART.refshard... -o ref.exr`: a reference
// render's (bake/reference/reference_shard.h). `lightbake merge PART.texshard... -o out.glb`: an
// export's direct light (app/export_shard.h). Each kind's checks and sums are in bake/; here
// the outputs, loading and console.

#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "app/bake_summary.h"
#include "app/commands.h"
#include "app/console_progress.h"
#include "app/export_shard.h"
#include "app/load.h"
#include "app/output_path.h"
#include "app/radiance_output.h"
#include "app/thread_option.h"
#include "bake/export/export_shard.h"
#include "bake/hq/render_shards.h"
#include "bake/io/image_io.h"
#include "bake/pipeline/bake_io.h"
#include "bake/pipeline/pass1_shard_io.h"
#include "bake/reference/reference_shard.h"
#include "bake/reference/report.h"
#include "bake/shards/shard_file.h"

namespace lb::app {

namespace {

struct MergeOptions {
  std::vector<std::string> shards;
  std::string output;  // default: render.exr for render shards, bake for pass-1 shards
  std::string scene;   // pass-1 and export shards: the scene, if not where they recorded it
  std::string bake;    // export shards: the bake, if not where they recorded it
  bool directional_share = false;  // directional export shards: s in the file
  bool force = false;
  bool quiet = false;
};

// A merged image's checks before any work: .exr or .png, and neither it nor its report
// (returned: OUTPUT.json) replaces a file lightbake did not write unless `force`.
std::string prepare_merged_image(const std::string& output, bool force) {
  if (!is_radiance_image_path(output)) fail(output + ": output must be .exr or .png");
  const std::string report_path = shards::shard_report_path(output);
  prepare_output_file(output, force);
  prepare_output_file(report_path, force);
  return report_path;
}

void merge_pass1(const MergeOptions& options) {
  const Pass1ShardSet set = read_pass1_shard_set(options.shards);
  const std::string scene_path = options.scene.empty() ? set.scene_path : options.scene;
  const std::string output_dir = options.output.empty() ? "bake" : options.output;
  check_bake_destination(output_dir, options.force);  // now, not after the bake
  const Scene scene = load_or_exit(scene_path);
  try {
    const ConsoleProgress console(options.quiet);
    const BakeResult bake = bake_from_pass1_shards(set, scene, scene_path, console.progress());
    SaveBakeOptions save;
    save.params = &set.params;
    save.force = options.force;
    save_bake(output_dir, scene, bake, save);
    std::printf("merged        %zu pass-1 shards of %s\n", set.shards.size(), scene_path.c_str());
    print_bake_summary(scene, bake, output_dir);
  } catch (const Cancelled&) {
    std::fprintf(stderr, "lightbake: merge cancelled; nothing written\n");
    throw ExitCode{130};
  }
}

void merge_reference(const MergeOptions& options) {
  const std::string output = options.output.empty() ? "reference.exr" : options.output;
  const std::string report_path = prepare_merged_image(output, options.force);
  const reference::MergedReference merged = reference::merge_reference_shards(options.shards);
  const reference::ReferenceParams& params = merged.params;
  ToneMap tone;
  try {
    tone.curve = parse_tone_curve(merged.settings.at("tone").at("curve").get<std::string>());
    tone.exposure = merged.settings.at("tone").at("exposure").get<float>();
  } catch (const std::exception&) {
    fail(merged.report_path + ": tone settings missing or unknown");
  }
  const reference::ReportInfo info{merged.scene_path, output,
                                   merged.settings.at("camera").get<std::string>()};
  nlohmann::json report =
      nlohmann::json::parse(reference::report_json(info, params, merged.film, merged.stats));
  report["merged_from"] = options.shards;
  report["shard_count"] = merged.shard_count;
  // Seconds over the shards: CPU summed, wall the longest shard's.
  write_radiance_image_and_report(output,
                                  reference::window_in_image(merged.film.average(), params),
                                  params.width, params.height, tone, report_path,
                                  std::move(report));
  const reference::NoiseEstimate noise = merged.film.noise();
  std::printf("merged     %d reference shards into %s (%dx%d, %d spp), %s\n", merged.shard_count,
              output.c_str(), params.width, params.height, merged.film.passes(),
              report_path.c_str());
  std::printf("noise      %.2f%% per pixel (RMS), %.3f%% on the image mean\n",
              100.0 * noise.pixel_relative_standard_error,
              100.0 * noise.mean_relative_standard_error);
}

void merge_render(const MergeOptions& options) {
  const std::string output = options.output.empty() ? "render.exr" : options.output;
  const std::string report_path = prepare_merged_image(output, options.force);
  MergedRender merged = merge_render_shards(options.shards);
  ToneMap tone;
  tone.curve = parse_tone_curve(merged.report["tone"].value("curve", "aces"));
  tone.exposure = merged.report["tone"].value("exposure", 0.0f);
  merged.report["output"] = output;
  write_radiance_image_and_report(output, merged.pixels, merged.width, merged.height, tone,
                                  report_path, std::move(merged.report));
  std::printf("merged     %zu shards into %s (%dx%d), %s\n", options.shards.size(),
              output.c_str(), merged.width, merged.height, report_path.c_str());
}

// The kind of the shards, by their extension: one kind, one of the four.
const shards::ShardKind& kind_of(const std::vector<std::string>& paths) {
  static constexpr const shards::ShardKind* kinds[] = {&kRenderShard, &kPass1Shard,
                                                       &reference::kReferenceShard, &kExportShard};
  const std::string extension = lowercase_extension(paths.front());
  for (const shards::ShardKind* kind : kinds) {
    if (extension != kind->extension) continue;
    for (const std::string& path : paths)
      if (lowercase_extension(path) != extension)
        fail("merge: give shards of one kind, not both (" + extension + " and " + path + ")");
    return *kind;
  }
  fail(paths.front() + ": not a shard; merge takes .rendershard (render), .refshard "
       "(reference), .pass1 (bake) or .texshard (export) files");
}

void run_merge(const MergeOptions& options) {
  const shards::ShardKind& kind = kind_of(options.shards);
  if (&kind == &kPass1Shard) return merge_pass1(options);
  if (&kind == &kExportShard)
    return merge_export_shards({options.shards,
                                options.output.empty() ? "export.glb" : options.output,
                                options.scene, options.bake, options.directional_share,
                                options.force, options.quiet});
  if (!options.bake.empty()) fail("--bake: only for export shards (.texshard)");
  if (options.directional_share) fail("--directional-share: only for export shards (.texshard)");
  if (!options.scene.empty()) fail("--scene: only for pass-1 and export shards");
  if (&kind == &reference::kReferenceShard) return merge_reference(options);
  merge_render(options);
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
                  "The shards: .rendershard render tiles, .pass1 sums, .refshard reference sums "
                  "or .texshard export texels (their .json beside them)")
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
  cmd->add_flag("--directional-share", options->directional_share,
                "Directional export shards: the x map as RGBA with the direct term's share s "
                "in its alpha, 13/3 of the plain map's bytes instead of 4x (docs/export.md)");
  cmd->add_flag("--force", options->force,
                "Replace the image or its .json report even if lightbake did not write them; "
                "write a bake into a folder that holds no bake");
  cmd->add_flag("-q,--quiet", options->quiet, "Pass-1 and export shards: no progress lines");
  add_threads_option(*cmd);
  cmd->callback([options] { run_merge(*options); });
}

}  // namespace lb::app
