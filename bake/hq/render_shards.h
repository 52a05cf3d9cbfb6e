#pragma once
// Render shards (`lightbake render SCENE BAKE --shard i/n -o PART.rendershard`) in the shard
// container (bake/shards/shard_file.h) and their merge (`lightbake merge PART.rendershard... -o
// OUT.exr|png`). A shard renders the tiles t with t mod n = i (hq_render.h):
//
//   payload   the pixels of its tiles (3 x f32, W/(sr m^2)), row by row, top row first
//   settings  camera, width, height, samples_per_side, passes, seed, max_depth, final_gather,
//             terms, scene_hash, bake_hash, tone, tile_size; the report also holds "bake",
//             "rays" (the render report's table), "render_seconds" and "bake_seconds"
//
// Every pixel comes from the one shard that rendered its tile: the merge has the unsharded
// render's bits.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "bake/scene.h"
#include "bake/shards/shard_file.h"

namespace lb {

inline constexpr shards::ShardKind kRenderShard{
    shards::ShardTag::render, "render", "a render shard",
    "its tiles' pixels; lightbake merge makes the image", ".rendershard", "render", "render", 1};

// What every shard of one render shares (compared key by key by merge), from the render's
// report (hq/ray_report.h, with "terms", "scene_hash", "bake_hash" and "tone").
nlohmann::json render_shard_settings(const nlohmann::json& render_report, int tile_size);

// Writes PART.rendershard, then PART.json: the tiles of shard `index` of `count` of `pixels`
// (width x height, the settings'). `render_report`: the run's, for what it measured.
void write_render_shard(const std::string& data_path, const std::string& scene_path,
                        const std::string& bake_dir, const nlohmann::json& settings, int index,
                        int count, const std::vector<vec3>& pixels,
                        const nlohmann::json& render_report);

struct MergedRender {
  std::vector<vec3> pixels;  // width x height, row 0 at the top, W/(sr m^2)
  int width = 0, height = 0;
  nlohmann::json report;     // their settings ("tone" too), merged_from, seconds and rays summed
};

// Throws (one line naming the file) for a missing or repeated shard, a shard of another scene,
// bake, setting or count, and data that is not its report's or not its tiles' size.
MergedRender merge_render_shards(const std::vector<std::string>& paths);

}  // namespace lb
