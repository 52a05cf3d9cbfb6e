#pragma once
// The merge of a render's shards (`lightbake render --shard i/n -o PART.exr`, joined by
// `lightbake merge PART.exr... -o OUT.exr|png`). A render shard is an image of its tiles' pixels
// (zeros elsewhere, so it stays viewable) beside the render's report, which records
// "shard": {"index", "count", "tile_size"} and the image's "image": {"file", "bytes", "fnv1a"}.
// The set is checked by the shard container's functions (bake/shards/shard_file.h); every pixel
// comes from the one shard that rendered its tile, so the merge has the unsharded render's bits.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "bake/io/image_io.h"
#include "bake/scene.h"

namespace lb {

struct MergedRender {
  std::vector<vec3> pixels;  // width x height, row 0 at the top, W/(sr m^2)
  int width = 0, height = 0;
  ToneMap tone;              // the shards'
  nlohmann::json report;     // their shared settings, merged_from, seconds and rays summed
};

// Throws (one line naming the file) for a missing or repeated shard, a shard of another scene,
// bake, setting or count, and an image that is not its report's (size or FNV-1a).
MergedRender merge_render_shards(const std::vector<std::string>& paths);

}  // namespace lb
