#pragma once
// Shards of the export's direct-light bake (`lightbake export SCENE BAKE --contents all --shard
// i/n -o PART.texshard`) in the shard container (bake/shards/shard_file.h), and their merge
// (`lightbake merge PART.texshard... -o out.glb|gltf`). A shard bakes the direct term of one
// range of the lightmap's node rows, about 1/n of the work (bake/lightmap/texel_footprint.h,
// partition_texel_rows: every node it bakes has the bits of the unsharded export's):
//
//   payload   u32 first row, end row (one past the last), then per node row in row order its
//             direct term (width x 3 f32, W/(sr m^2)); directional shards (`--directional`,
//             directional_lightmap.h's DirectBand) follow each row's term with its L1 (width x
//             3 axes x 3 f32, x y z) and a byte per node, 1 where visible surface was estimated;
//             shards whose settings say `unshadowed` put the term's ratio estimator's
//             denominator (width x 3 f32: Lightmap::direct_unshadowed) right after the term
//   settings  scene_hash, bake_hash, contents, direct_samples, lightmap_format,
//             lightmap_encoding, atlas_width, atlas_height, denoise (the merge runs the
//             denoiser on the joined term; absent before it: false), directional and
//             directional_share (absent before them: false), shadow_side (--shadow-rays;
//             absent before it: 0), unshadowed (absent before it: false, the merge samples
//             the denominator itself); the report also holds
//             "bake" (the directory), "rows" {begin, end}, "shadow_rays", "points", "seconds"
//
// Merge joins the rows (shard i's must begin where shard i - 1's end); the export written from
// them has the bytes of `lightbake export SCENE BAKE --contents all [--directional]` with the
// same settings (a directional merge makes the soft and caustic terms' bands as that export
// does, from the bake).

#include <string>
#include <vector>

#include "bake/export/gltf_export.h"
#include "bake/lightmap/directional_lightmap.h"
#include "bake/lightmap/lightmap.h"
#include "bake/shards/shard_file.h"

namespace lb {

// 2: one range of rows per shard (1: bands b with b mod n = i).
inline constexpr shards::ShardKind kExportShard{
    shards::ShardTag::export_texels, "export", "an export shard",
    "its texels; lightbake merge writes the glTF", ".texshard", "export", "export", 2};
inline constexpr int kMaxExportShards = 65536;

// Where a shard's lightmap came from and how the merge is to write it.
struct ExportShardSource {
  std::string scene_path, bake_dir;
  std::string scene_hash, bake_hash;
  std::string lightmap_format = "exr", lightmap_encoding = "srgb";
  int direct_side = 0;
  bool denoise = false;            // the merge denoises the joined direct term (LightmapParams)
  bool directional = false;        // the shard holds the direct term's L1 too (DirectBand)
  bool directional_share = false;  // the merge writes s (GltfExportOptions::directional_share)
  int shadow_side = 0;             // LightmapParams::shadow_side (--shadow-rays)
};

// Writes PART.texshard, then PART.json: the direct term of `lightmap.direct_rows`.
void write_export_shard(const std::string& data_path, const ExportShardSource& source,
                        const Lightmap& lightmap, int index, int count, double seconds);
// The same for a directional shard: the direct band of `band.rows` (source.directional).
void write_export_shard(const std::string& data_path, const ExportShardSource& source,
                        const DirectBand& band, int index, int count, double seconds);

struct ExportShardSet {
  std::vector<shards::ShardFile> shards;  // in index order
  GltfExportOptions gltf;                 // contents all, the shards' format and samples
  int width = 0, height = 0;              // the atlas's
  bool unshadowed = false;                // the shards hold the ratio's denominator too
  std::string scene_path, bake_dir;       // as the first shard recorded them
};
// One complete set; throws naming the file otherwise (shard_file.h).
ExportShardSet read_export_shard_set(const std::vector<std::string>& paths);

// The atlas's direct term (`l0`), with its L1 and filled nodes for directional shards, joined
// from the shards' rows; throws naming a shard whose data is not its report's or whose rows do
// not follow the shard before.
DirectBand join_export_shards(const ExportShardSet& set);

}  // namespace lb
