#pragma once
// A bake directory on disk, written under a temporary name and renamed into place
// (AtomicDirectory), so a crash or a cancel never leaves half a bake:
//
//   manifest.json     format and version, scene path and hash, mesh count, seed, settings,
//                     ray counts, seconds and statistics of both passes, the files below
//   illumination.exr  the caustic atlas, RGB float32, W/(sr m^2) (bake_result.h convention);
//                     the atlas covers every diffuse mesh (0 where no caustic fell); absent
//                     only when the scene has no diffuse mesh (width = height = 0)
//   illumination.bin  the rest of IlluminationMaps (format below)
//   radiosity.bin     the radiosity meshes with their vertex radiance (format below)
//   soft_light.exr    the soft-light texel map (bake/lightmap/soft_texels.h), RGB float32,
//                     W/(sr m^2), the atlas's size; absent where the atlas is
//   illumination_l1{x,y,z}.exr, soft_light_l1{x,y,z}.exr   with the `directional` setting: the
//                     caustic and soft maps' L1 bands (bake/sh_projection.h), RGB float32, one
//                     per world axis; a bake of version 5 (6) reads without (the soft) band
//
// Binary files are little-endian, with no padding, and end in a u64 checksum: the FNV-1a 64 of
// every byte before it (binary_file.h):
//   illumination.bin: "LBILLUM4", u32 width, u32 height, f32 texel_size (m), f32 texel_area[w*h],
//     u8 valid[w*h], u32 mesh_count, then per mesh: u32 n, f32 lightmap_uv[2*n], u32 c,
//     u32 copied_from[c], u32 t, u32 triangles[3t] (the atlas's VertexSplit; c = t = 0 where
//     nothing was split), f32 mesh texel size (m, 0 = no map)
//   radiosity.bin: "LBRADIO2", u32 mesh_count, then per mesh: u32 vertex_count (0: the mesh
//     has no radiosity and nothing follows), u32 triangle_count, u32 attribute flags (1 normals,
//     2 uvs, 4 lightmap_uvs, 8 tangents), i32 material, u32 name length, name bytes,
//     f32 positions[3v], [f32 normals[3v]], [f32 uvs[2v]], [f32 lightmap_uvs[2v]],
//     [f32 tangents[4v]], u32 triangles[3t], f32 vertex_radiance[3v], u32 triangle_patch[t]
//
// The manifest's "checksums" records every file by name: an .exr's FNV-1a 64 of its bytes, a
// .bin's trailing checksum (16 hex digits).
//
// load_bake checks the bake belongs to the scene (mesh count and scene_hash below, which covers
// every input file's content) and every file's checksum (its own trailer, the manifest's
// record: a file damaged or taken from another bake), and throws std::runtime_error naming the
// file otherwise.
//
// Saving never loses a user's files: it replaces a previous bake directory (recognised by its
// manifest) or fills an empty or new folder; any other existing folder is refused unless
// `force`. Files in the folder that a bake does not write (a render, notes) are kept either way.

#include <nlohmann/json_fwd.hpp>
#include <string>

#include "bake/bake_result.h"
#include "bake/pipeline/bake.h"

namespace lb {

struct SaveBakeOptions {
  const BakeParams* params = nullptr;  // recorded in the manifest when given
  bool force = false;  // also write into a folder that holds something other than a bake
};

void save_bake(const std::string& directory, const Scene& scene, const BakeResult& bake,
               const SaveBakeOptions& options = {});
// Same, recording the settings used in the manifest.
void save_bake(const std::string& directory, const Scene& scene, const BakeResult& bake,
               const BakeParams& params);

// The most a bake's files take on disk with an atlas of `atlas_width` x `atlas_height` texels,
// bytes: per texel its two maps (and each light group's two) as if 32-bit float RGBA EXR
// uncompressed (they are float RGB, zip: 3-11 bytes) and 8 of illumination.bin (5 measured);
// per triangle 64 of radiosity.bin (36 measured on the room and a 324k-triangle level); 1 MiB
// for the manifest; `directional`: the caustic and soft maps' three L1 maps each too. Known
// once the atlas is planned (BakeCallbacks::on_atlas), before any ray.
double bake_files_bytes(const Scene& scene, int atlas_width, int atlas_height,
                        bool directional = false);

// Throws std::runtime_error naming `directory` if save_bake would refuse it: call before a long
// bake so the user learns in a second. `directory` may be absent, an empty folder or a bake.
void check_bake_destination(const std::string& directory, bool force);
bool is_bake_directory(const std::string& directory);  // has a lightbake bake manifest
BakeResult load_bake(const std::string& directory, const Scene& scene);  // throws on mismatch
// The settings a bake directory's manifest records (every setting of bake_settings.h and the
// level): `bake --like DIR` bakes with them. Throws std::runtime_error naming the manifest if
// it records none or a value that is unknown or out of range.
BakeParams read_bake_settings(const std::string& directory);
// The manifest's "settings" object: every setting by its key and the level.
nlohmann::json bake_settings_json(const BakeParams& params);
// Reads it back; throws std::runtime_error "WHERE: settings.KEY: ..." on an unknown key or a
// value out of range, or "WHERE: records no bake settings ..." when it is not such an object.
BakeParams bake_settings_from_json(const nlohmann::json& settings, const std::string& where);

// FNV-1a over what a bake depends on: every mesh's positions, indices and attributes, the
// materials, lamps and sky, and every texture's texels (so an edited texture or sky image
// makes an old bake refused). Hex, 16 digits.
std::string scene_hash(const Scene& scene);
// FNV-1a over the baked light (maps, soft-light texels, radiosity meshes and their vertex
// radiance) and the seed: tells whether two renders used the same bake. Hex, 16 digits.
std::string bake_hash(const BakeResult& bake);

}  // namespace lb
