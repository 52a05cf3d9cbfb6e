#include "app/merge_bake.h"

#include <cstdio>
#include <nlohmann/json.hpp>

#include "app/bake_summary.h"
#include "app/commands.h"
#include "app/console_progress.h"
#include "app/load.h"
#include "app/shard_set.h"
#include "bake/pipeline/bake_io.h"
#include "bake/pipeline/pass1_shard_io.h"

namespace lb::app {

namespace {

// The shards, one per index, all of one bake; fail() (or a std::runtime_error naming the
// report) otherwise.
std::vector<Pass1ShardReport> read_complete_set(const std::vector<std::string>& paths) {
  std::vector<Pass1ShardReport> shards;
  for (const std::string& path : paths) shards.push_back(read_pass1_shard_report(path));
  const nlohmann::json shared = pass1_shard_shared(shards.front().report);
  const int count = shards.front().count;
  if (count < 1) fail(shards.front().report_path + ": shard count " + std::to_string(count));
  std::vector<std::string> data_paths;
  std::vector<int> indices;
  for (const Pass1ShardReport& shard : shards) {
    const nlohmann::json mine = pass1_shard_shared(shard.report);
    const auto differs = [&](const std::string& what, const nlohmann::json& a,
                             const nlohmann::json& b) {
      fail(shard.data_path + ": " + what + " " + a.dump() + " differs from " +
           shards.front().data_path + "'s " + b.dump() + ": not a shard of the same bake");
    };
    for (const char* key : {"scene_hash", "seed"})
      if (mine[key] != shared[key]) differs(key, mine[key], shared[key]);
    const nlohmann::json &settings = mine["settings"], &first_settings = shared["settings"];
    for (auto it = first_settings.begin(); it != first_settings.end(); ++it)
      if (settings.value(it.key(), nlohmann::json()) != it.value())
        differs("settings." + it.key(), settings.value(it.key(), nlohmann::json()), it.value());
    for (const char* key : {"settings", "shard_count", "atlas"})
      if (mine[key] != shared[key]) differs(key, mine[key], shared[key]);
    data_paths.push_back(shard.data_path);
    indices.push_back(shard.index);
  }
  shards_by_index(data_paths, indices, count);
  return shards;
}

}  // namespace

void merge_bake_shards(const BakeMergeOptions& options) {
  const std::vector<Pass1ShardReport> shards = read_complete_set(options.shards);
  const Pass1ShardReport& first = shards.front();
  const std::string scene_path =
      options.scene_path.empty() ? first.report.at("scene").get<std::string>() : options.scene_path;
  check_bake_destination(options.output_dir, options.force);  // now, not after the bake
  const Scene scene = load_or_exit(scene_path);
  const std::string hash = scene_hash(scene);
  if (hash != first.report.at("scene_hash").get<std::string>())
    fail(scene_path + ": scene hash " + hash + " differs from the shards' " +
         first.report.at("scene_hash").get<std::string>() + " (" + first.report_path +
         "): not the scene they baked");
  const BakeParams params = bake_settings_from_json(first.report.at("settings"), first.report_path);
  const nlohmann::json& atlas = first.report.at("atlas");
  illumination::Pass1Sums sums(size_t(atlas.at("width").get<int>()) *
                               size_t(atlas.at("height").get<int>()));
  for (const Pass1ShardReport& shard : shards) add_pass1_shard_sums(shard, sums);
  try {
    const ConsoleProgress console(options.quiet);
    const BakeResult bake = bake_from_pass1_sums(scene, params, sums, console.progress());
    SaveBakeOptions save;
    save.params = &params;
    save.force = options.force;
    save_bake(options.output_dir, scene, bake, save);
    std::printf("merged        %zu pass-1 shards of %s\n", shards.size(), scene_path.c_str());
    print_bake_summary(scene, bake, options.output_dir);
  } catch (const Cancelled&) {
    std::fprintf(stderr, "lightbake: merge cancelled; nothing written\n");
    throw ExitCode{130};
  }
}

}  // namespace lb::app
