#pragma once
// The lightmap atlas: one texture that holds the illumination maps of the diffuse meshes the
// caller includes (the bake includes every diffuse mesh: the exported lightmap covers them all).
// Charts are grown over edge-adjacent faces with similar normals (OpenMesh adjacency), projected
// onto their plane at a uniform texel size (the thin ones unfolded into strips instead,
// atlas_unfold.h) and packed with padding. A mesh that brings its own `lightmap_uvs` (glTF
// TEXCOORD_1) keeps their layout when they are sound (given_uvs.h): each UV island becomes a
// chart, scaled uniformly (the mesh's texel density) and packed like the others; UVs that fold
// or overlap are replaced by generated ones with a warning, as are all with
// `generate_lightmap_uvs`.
//
// Texel nodes. The map is read with bilinear filtering, so each texel is a node at its centre
// ((i + 0.5) / width, (j + 0.5) / height) and light at a surface point belongs to the four
// nodes around it with bilinear weights (Arvo). A node's area is the integral of its bilinear
// weight over the surface, computed exactly (triangles clipped to the node cells), so a
// uniform power density rho (W/m^2) deposited anywhere gives every node the value rho / pi,
// at chart borders as well as inside: there is no seam where a chart boundary crosses a wall.
//
// Padding. A chart e texels wide lies centred between two node centres ceil(e) apart, so it
// touches ceil(e) + 1 node columns (one fewer than if its corner lay on a texel edge, and the
// outermost ones hold at least 1/8 of a node's area): its rectangle (`offset`, `size` =
// ceil(e) - 1 texels) grown by one node each side. With
// padding >= 2 between rectangles no node is shared by two charts. The default of 3 leaves one
// empty node between them, which dilation fills so mipmaps and filtering never see black. The
// atlas border leaves padding / 2 - 1 empty nodes (none at 2 or 3): maps are read with
// CLAMP_TO_EDGE and no chart's bilinear footprint reaches past its own nodes.
//
// Automatic texel size: max(scene diagonal / 256, sqrt(included area / (0.25 * max_size^2))),
// i.e. about 2.4 cm in a 4 x 4 x 2.5 m room, and grown by 1.2x until the packing fits in
// max_size^2. A mesh's own bake.texel_size wins over the params, which win over the rule.
//
// Vertex splits. Lightmap UVs are per vertex (the Mesh contract), so where two charts of a
// smooth mesh meet, their shared vertices are split: the atlas returns the split per mesh
// (`vertex_splits`, triangle order kept) and its UVs index the split vertices. Consumers apply
// it with split_vertices (scene.h) before they attach the UVs; the geometry does not change.

#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "bake/scene.h"

namespace lb {

struct AtlasParams {
  float texel_size = 0.0f;        // metres per texel; 0 = the automatic rule above
  int max_size = 2048;            // largest atlas edge, texels
  int padding = 3;                // texels between chart rectangles (half at the border), >= 2
  float chart_angle_deg = 40.0f;  // a face joins a chart if its normal is this close to the seed's
  // Unwrap every mesh, also those that bring their own lightmap UVs (which are otherwise kept
  // when they neither fold nor overlap).
  bool generate_lightmap_uvs = false;
  // Per scene mesh, metres (the pass's caustic pilot, illumination.h); 0 or missing = the
  // texel_size above. A mesh's own bake.texel_size still wins.
  std::vector<float> mesh_texel_size;
};

struct AtlasChart {
  int mesh = -1;
  std::vector<uint32_t> triangles;
  glm::ivec2 offset{0};  // lower-left texel of the chart's rectangle
  glm::ivec2 size{0};    // rectangle, texels (>= 0); its nodes grown by one hold the chart
  float texel_size = 0.0f;
  bool given_uvs = false;  // laid out from the mesh's own lightmap_uvs
};

struct Atlas {
  int width = 0;
  int height = 0;
  float texel_size = 0.0f;  // the texel size used for meshes without their own setting
  // Per scene mesh: atlas UVs in [0,1]^2 per vertex of the split mesh, or empty if the mesh
  // is not in the atlas; and the split (empty when no vertex had to be split).
  std::vector<std::vector<vec2>> lightmap_uvs;
  std::vector<VertexSplit> vertex_splits;
  std::vector<float> mesh_texel_size;  // metres per texel per scene mesh, 0 where no map
  std::vector<float> texel_area;       // m^2 per node, width*height, row j = v * height - 0.5
  std::vector<uint8_t> valid;          // 1 where texel_area > 0
  std::vector<AtlasChart> charts;
  std::vector<std::string> warnings;  // overlaps in given UVs, meshes left out

  bool has_map(size_t mesh) const {
    return mesh < lightmap_uvs.size() && !lightmap_uvs[mesh].empty();
  }
  // The triangles `lightmap_uvs[mesh]` is indexed by.
  const std::vector<uvec3>& triangles_of(const Scene& scene, size_t mesh) const {
    return mesh < vertex_splits.size() && !vertex_splits[mesh].empty()
               ? vertex_splits[mesh].triangles
               : scene.meshes[mesh].triangles;
  }
  size_t node_index(int i, int j) const { return size_t(j) * size_t(width) + size_t(i); }
};

// Builds the atlas for the meshes with include[mesh] set (diffuse receivers).
Atlas build_atlas(const Scene& scene, const std::vector<bool>& include, const AtlasParams& params);

// The automatic texel size for the included meshes (before any growth to fit max_size).
float automatic_texel_size(const Scene& scene, const std::vector<bool>& include, int max_size);

// The four nodes around a surface point and their bilinear weights (Arvo's splat, and the
// lookup a GPU does with bilinear filtering). Returns false if the mesh has no map.
struct NodeWeights {
  size_t index[4];
  float weight[4];
};
bool node_weights(const Atlas& atlas, const Scene& scene, uint32_t mesh, uint32_t triangle,
                  vec2 barycentric, NodeWeights& out);
NodeWeights node_weights_at_uv(const Atlas& atlas, vec2 uv);

// Node power (W) to the stored convention: power / (node area * pi), W/(sr m^2).
std::vector<vec3> power_to_radiance(const Atlas& atlas, const std::vector<glm::dvec3>& power);

// Fills invalid nodes next to valid ones with the mean of their valid neighbours, `rings`
// times, so bilinear filtering at chart borders never pulls in empty texels.
void dilate(const Atlas& atlas, std::vector<vec3>& radiance, int rings);

// Bilinear lookup at an atlas UV, as the GPU does it (clamped at the atlas border).
vec3 sample_map(const Atlas& atlas, const std::vector<vec3>& radiance, vec2 uv);

}  // namespace lb
