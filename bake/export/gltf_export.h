#pragma once
// A bake -> glTF 2.0 (.glb or .gltf, self-contained) for game engines and the web.
// What goes where, the lightmap encoding and how engines consume it: docs/export.md.
//
//   meshes     one glTF mesh + node per scene mesh, world space under one root node (whose
//              translation is Scene::world_origin), with the atlas's vertex splits applied
//              (mesh_with_lightmap): the scene's own surface, not the refined radiosity mesh.
//   TEXCOORD_1 lightmap UVs (every diffuse mesh has them).
//   lightmap   the complete baked light of the diffuse meshes (bake/lightmap/lightmap.h):
//              contents `indirect` = caustics + soft light (radiosity resampled into the
//              texels), `all` = + direct light from the area lights. As an 8-bit sRGB PNG
//              holding radiance / scale (scale = the map's largest value, so nothing clips),
//              bound by MOZ_lightmap {index, texCoord: 1, intensity = pi * scale}; extras name
//              units, encoding, contents and texel density; half-float EXR and/or Radiance HDR
//              beside the file. No COLOR_0: the lightmap holds all the baked light.
//   materials  metallic-roughness as the glTF loader reads them back (docs/gltf.md).
// No OpenGL; tinygltf writes the file.

#include <cstddef>
#include <string>
#include <vector>

#include "bake/bake_result.h"
#include "bake/io/image_io.h"
#include "bake/lightmap/directional_lightmap.h"
#include "bake/lightmap/lightmap.h"
#include "bake/probe_grid.h"
#include "bake/progress.h"

namespace lb {

// The 8-bit encodings of the illumination map, top row first (row 0 is v = 0, as glTF reads it:
// no flip), `scale` = the map's largest value, so nothing clips (docs/export.md):
//   srgb  RGB, byte = round(255 * srgb_oetf(radiance / scale)); decoded by the GPU's sRGB
//         sampler before filtering, so any engine draws it with one multiplier; ~0.4% steps
//         near the top, few codes for what is dim next to a bright caustic.
//   rgbm  RGBA, linear: m = ceil(255 * max(radiance) / scale) / 255 (at least 1/255), byte_c =
//         round(255 * radiance_c / (m * scale)), alpha = 255 m; decoded
//         radiance = rgb / 255 * alpha / 255 * scale in the shader (after filtering, which mixes
//         texels of different m: exact only at texel centres). A texel keeps 8 bits of its own
//         brightness wherever it lies below the scale.
enum class LightmapEncoding { srgb, rgbm };

inline constexpr char kLightProbesExtension[] = "LIGHTBAKE_light_probes";
const char* to_string(LightmapEncoding encoding);
LightmapEncoding parse_lightmap_encoding(const std::string& text);  // throws std::invalid_argument

struct LightmapPng {
  int width = 0;
  int height = 0;
  LightmapEncoding encoding = LightmapEncoding::srgb;
  int channels = 3;                // 3 (srgb) or 4 (rgbm)
  float scale = 1.0f;              // W/(sr m^2) per unit of decoded (linear) value
  std::vector<uint8_t> bytes;      // width*height*channels
  std::vector<unsigned char> png;  // the encoded file
};
LightmapPng encode_lightmap_png(int width, int height, const std::vector<vec3>& radiance,
                                LightmapEncoding encoding = LightmapEncoding::srgb);
// The radiance texel i holds, W/(sr m^2), decoded as the file's extras say.
vec3 decode_lightmap_texel(const uint8_t* texel, LightmapEncoding encoding, float scale);
// The map as a linear float image (RGB, W/(sr m^2)), for the EXR/HDR written beside the glTF.
Image lightmap_image(int width, int height, const std::vector<vec3>& radiance);

struct GltfExportInfo {
  size_t meshes = 0;
  size_t triangles = 0;
  size_t vertices = 0;
  size_t lightmapped_meshes = 0;
  int map_width = 0;  // 0 when the scene has no diffuse mesh (no map, no EXR/HDR)
  int map_height = 0;
  float map_scale = 0.0f;
  float texel_density = 0.0f;  // texels per metre (the atlas's default)
  LightmapContents contents = LightmapContents::indirect;
  uint64_t shadow_rays = 0;        // direct light (contents all)
  bool denoised = false;           // the direct term went through Open Image Denoise
  DenoiseStats denoise;            // what it did (denoise_texels.h)
  double lightmap_seconds = 0;     // wall seconds of bake_lightmap
  bool directional = false;        // the L1 band was written (LIGHTBAKE_lightmap_directional)
  double directional_seconds = 0;  // wall seconds of the L1 band's own work
  size_t bytes = 0;                // size of the glTF file written
  size_t png_bytes = 0;            // the 8-bit lightmap's PNG
  size_t ktx2_bytes = 0;           // its KTX2 (GltfExportOptions::ktx2_encoder), 0 without
  bool ktx2_mipmaps = false;       // the KTX2 holds the full mip chain (sides multiples of 4)
  size_t group_layers = 0;         // light groups' maps (LIGHTBAKE_lightmap_groups)
  std::vector<std::string> files;  // every file written, the glTF first
};

// Radiance files written beside the glTF: NAME.lightmap.exr (half float) and/or
// NAME.lightmap.hdr (Radiance RGBE), both in W/(sr m^2), E/pi.
enum class LightmapFormat { exr, hdr, both };
const char* to_string(LightmapFormat format);
LightmapFormat parse_lightmap_format(const std::string& text);  // throws std::invalid_argument

struct GltfExportOptions {
  LightmapContents contents = LightmapContents::indirect;
  LightmapFormat format = LightmapFormat::exr;
  LightmapEncoding encoding = LightmapEncoding::srgb;  // of the PNG inside the glTF
  // The `basisu` encoder (ktx2_encode.h): when set, the map is also stored as KTX2 UASTC, bound
  // by KHR_texture_basisu with the PNG as the fallback source. Empty: PNG only.
  std::string ktx2_encoder;
  int direct_side = 0;  // LightmapParams::direct_side (contents all; 0: automatic)
  int shadow_side = 0;  // LightmapParams::shadow_side (contents all; 0: a ray from every point)
  bool stitch_seams = true;  // LightmapParams::stitch_seams: off only to measure what it fixes
  bool denoise_direct = false;  // LightmapParams::denoise_direct (contents all; needs OIDN)
  // Contents all: the direct term already baked (the shards of `lightbake export --shard`
  // joined by merge), the atlas's width x height; null = bake it.
  const std::vector<vec3>* direct_light = nullptr;
  // With direct_light (may be null): its ratio estimator's denominator, joined from the same
  // shards (Lightmap::direct_unshadowed); null: sampled again.
  const std::vector<vec3>* direct_unshadowed = nullptr;
  // Directional maps (issue 38, `--directional`): the L1 band of the map as three more
  // textures bound by LIGHTBAKE_lightmap_directional (gltf_directional.h); export_gltf bakes
  // them (`directional_params`) and points `directional_maps` at them.
  bool directional = false;
  // The x map as RGBA with s, the direct term's share of L0, in its alpha (`"share": true`,
  // `--directional-share`): 13/3 of the plain map's bytes. Off: three RGB maps, 4x, s = 0.
  bool directional_share = false;
  DirectionalParams directional_params;
  const DirectionalMaps* directional_maps = nullptr;
  // The direct term's L0 and L1 already baked (export shards joined by merge); null = bake it.
  const DirectBand* direct_band = nullptr;
  // Light groups (issue 39): a bake with groups exports each group's map as a layer of its
  // own, bound by LIGHTBAKE_lightmap_groups (gltf_light_groups.h) beside MOZ_lightmap's sum;
  // export_gltf bakes them and points `group_lightmaps` at them (one per bake.light_groups).
  const std::vector<Lightmap>* group_lightmaps = nullptr;
  // Light probes (issue 38, docs/light-probes.md): the scene's moving objects are written as
  // nodes with `extras.dynamic` and no map, each with its blended probe light
  // (`extras.lightbake_probe_sh`, 27 numbers) when `dynamic_sh` has one per
  // Scene::dynamic_meshes entry; the grid as scene.extensions.LIGHTBAKE_light_probes when given.
  const ProbeGrid* light_probes = nullptr;
  const std::vector<ShL2>* dynamic_sh = nullptr;
  // Set by export_gltf from the path; callers of export_gltf_bytes set them themselves.
  bool binary = true;    // .glb; false: .gltf with buffers and images as data URIs
  std::string exr_name;  // file names beside the output, recorded in extras ("" = none)
  std::string hdr_name;
  std::string exr_fnv1a;  // their FNV-1a 64 (16 hex digits), recorded beside each name
  std::string hdr_fnv1a;
};

// The whole file in memory, for a lightmap made by bake_lightmap(scene, bake, ...).
std::vector<unsigned char> export_gltf_bytes(const Scene& scene, const BakeResult& bake,
                                             const Lightmap& lightmap,
                                             const GltfExportOptions& options,
                                             GltfExportInfo* info = nullptr);

// The files written beside `gltf_path`: "DIR/NAME.lightmap.exr" / ".hdr" for "DIR/NAME.glb".
std::string lightmap_exr_path(const std::string& gltf_path);
std::string lightmap_hdr_path(const std::string& gltf_path);
// Every path export_gltf(path, ..., options) writes, the glTF first.
std::vector<std::string> export_paths(const std::string& gltf_path,
                                      const GltfExportOptions& options);

// The most export_gltf(path, ...) writes for a bake whose atlas is `atlas_width` x
// `atlas_height` texels, bytes: per map (the whole light's, each light group's layer, the
// directional band's three) a half-float EXR and a Radiance HDR beside the glTF as if 16 and 4
// bytes a texel, 4 for its 8-bit copy inside (KTX2 another 4), x 4/3 for a .gltf's base64;
// 128 bytes a triangle of geometry; 1 MiB for the JSON. The lightmap's size is the atlas's, so
// this is known before the bake's first ray (BakeCallbacks::on_atlas).
double export_files_bytes(const Scene& scene, int atlas_width, int atlas_height,
                          const std::string& gltf_path, const GltfExportOptions& options);

// THE LIBRARY ENTRY POINT (the CLI and the viewer's Export button call it): makes the
// lightmap (progress stages "lightmap: ..."; Ctrl-C throws Cancelled, nothing written), then
// writes `path` (.glb or .gltf, by extension) and the EXR/HDR beside it: each under a
// temporary name first, all renamed into place only once every one is complete, so a failed
// write leaves nothing new behind. Throws std::runtime_error naming the path.
GltfExportInfo export_gltf(const std::string& path, const Scene& scene, const BakeResult& bake,
                           const GltfExportOptions& options = {}, const Progress& progress = {});

// True if `path` is a .glb or .gltf whose asset.generator starts with "lightbake".
bool is_lightbake_gltf(const std::string& path);

}  // namespace lb
