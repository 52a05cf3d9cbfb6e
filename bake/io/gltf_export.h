#pragma once
// A bake -> glTF 2.0 (.glb or .gltf, self-contained) for game engines and the web.
// What goes where, the lightmap encoding and how engines consume it: docs/export.md.
//
//   meshes     one glTF mesh + node per scene mesh, world space under one root node (whose
//              translation is Scene::world_origin). Diffuse meshes with radiosity are exported
//              as their refined radiosity meshes (the surface the vertex solution lives on);
//              the others with the atlas's vertex splits applied (make_baked_scene).
//   COLOR_0    vertex radiosity / color_scale, float RGB in [0, 1] as glTF requires; the
//              radiance (E/pi, W/(sr m^2), bake_result.h convention) is COLOR_0 x color_scale,
//              a power of two recorded in asset.extras.lightbake_color_0_scale (so exact).
//   TEXCOORD_1 lightmap UVs where a mesh has an illumination map.
//   lightmap   the caustic illumination map as an 8-bit sRGB PNG holding radiance / scale
//              (scale = the map's largest value, so nothing clips), bound by MOZ_lightmap
//              {index, texCoord: 1, intensity = pi * scale}; extras name units and encoding.
//   materials  metallic-roughness as the glTF loader reads them back (docs/gltf.md).
// No OpenGL; tinygltf writes the file.

#include <cstddef>
#include <string>
#include <vector>

#include "bake/bake_result.h"
#include "bake/io/image_io.h"

namespace lb {

// The 8-bit encoding of the illumination map: bytes = round(255 * srgb_oetf(radiance / scale)),
// RGB, top row first (row 0 is v = 0, as glTF reads it: no flip).
struct LightmapPng {
  int width = 0;
  int height = 0;
  float scale = 1.0f;              // W/(sr m^2) per unit of decoded (linear) value
  std::vector<uint8_t> rgb;        // width*height*3
  std::vector<unsigned char> png;  // the encoded file
};
LightmapPng encode_lightmap_png(const IlluminationMaps& maps);
// The smallest power of two >= the largest vertex radiance (1 when there is none): COLOR_0
// holds radiance / scale, exactly (a power-of-two division only changes the exponent).
float vertex_color_scale(const std::vector<std::vector<vec3>>& vertex_radiance);
// The map as a linear float image (RGB, W/(sr m^2)), for the EXR written beside the glTF.
Image lightmap_image(const IlluminationMaps& maps);

struct GltfExportInfo {
  size_t meshes = 0;
  size_t triangles = 0;
  size_t vertices = 0;
  size_t lightmapped_meshes = 0;
  size_t radiosity_meshes = 0;
  int map_width = 0;  // 0 when the bake has no illumination map (no PNG, no EXR)
  int map_height = 0;
  float map_scale = 0.0f;
  float color_scale = 1.0f;  // COLOR_0 x color_scale = vertex radiance
  size_t bytes = 0;          // size of the glTF file written
};

struct GltfExportOptions {
  bool binary = true;    // .glb; false: .gltf with buffers and images as data URIs
  std::string exr_name;  // file name of the EXR beside the output, recorded in extras
};

// The whole file in memory.
std::vector<unsigned char> export_gltf_bytes(const Scene& scene, const BakeResult& bake,
                                             const GltfExportOptions& options,
                                             GltfExportInfo* info = nullptr);

// The EXR path written beside `gltf_path`: "DIR/NAME.lightmap.exr" for "DIR/NAME.glb".
std::string lightmap_exr_path(const std::string& gltf_path);

// Writes `path` (.glb or .gltf, by extension) atomically, and the map as half-float EXR at
// lightmap_exr_path(path) when the bake has one. Throws std::runtime_error naming the path.
GltfExportInfo export_gltf(const std::string& path, const Scene& scene, const BakeResult& bake);

// True if `path` is a .glb or .gltf whose asset.generator starts with "lightbake".
bool is_lightbake_gltf(const std::string& path);

}  // namespace lb
