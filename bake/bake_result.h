#pragma once
// What the two bake passes produce, and how consumers (viewer, HQ renderer) see it.
//
// THE CONVENTION FOR STORED LIGHT (owned here, tested by the furnace tests):
// illumination maps and vertex radiosity store *incident* light before the surface's
// reflectance is applied, in linear RGB, as the radiance a white Lambertian surface would
// reflect: E / pi, in W/(sr m^2), where E is the irradiance in W/m^2 from that term alone.
// A renderer multiplies by the reflectance (and its texture) at shading time:
//   L_out = R * (direct + illumination_map + vertex_radiosity).
// The illumination map holds L S+ D light (one or more specular bounces, no diffuse one);
// vertex radiosity holds light that met two or more diffuse surfaces. Direct light (L D)
// is in neither: it is computed at view time.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "bake/scene.h"

namespace lb {

// ---- pass 1: illumination maps (caustics) --------------------------------------------

struct IlluminationStats {
  uint64_t feeler_rays = 0;
  uint64_t illumination_rays = 0;    // dense rays sent (primary), each may bounce
  uint64_t ray_casts = 0;            // every rtcIntersect call the pass made
  uint64_t zones_total = 0;
  uint64_t zones_traced = 0;         // zones that got dense rays
  vec3 power_sent{0.0f};             // W, through the traced zones
  vec3 power_deposited{0.0f};        // W, onto diffuse surfaces after >= 1 specular bounce
  vec3 power_absorbed{0.0f};         // W, absorbed by specular surfaces or roulette-neutral loss
  vec3 power_escaped{0.0f};          // W, left the scene
  vec3 power_direct{0.0f};           // W, hit a diffuse surface first (dropped: viewer's job)
  double seconds = 0.0;
  double feeler_seconds = 0.0;
  uint64_t emitter_hits = 0;         // illumination paths that ended on an emitter (absorbed)
  int64_t rays_saved = 0;            // rays tracing every zone would cost - rays sent - feelers
  double atlas_seconds = 0.0;        // atlas, filter, dilation; part of `seconds`
  // The caustic pilot (IlluminationParams::pilot_texels): its rays and deposits, and per scene
  // mesh the texel size it chose (0: the base size) and why: the densest pilot cell's
  // deposits per m^2 scaled to the full ray count (0: no caustic reached the mesh).
  uint64_t pilot_rays = 0;
  uint64_t pilot_deposits = 0;
  double pilot_seconds = 0.0;
  std::vector<float> pilot_texel_size;
  std::vector<float> pilot_peak_density;
};

// The atlas covers every diffuse mesh (the lightmap of the export, issue 12), whether or not
// any caustic reached it: texels no caustic reached hold 0. It is 0 x 0 only when the scene has
// no diffuse mesh, or none could be unwrapped.
struct IlluminationMaps {
  int width = 0;  // atlas size in texels
  int height = 0;
  std::vector<vec3> radiance;      // width*height, W/(sr m^2), the convention above
  std::vector<float> texel_area;   // m^2 of surface each texel node stands for (0 = unused)
  std::vector<uint8_t> valid;      // 1 where a texel node lies on some chart
  // Per scene mesh: the mesh's lightmap UVs into this atlas, or empty if it has no map. Where
  // charts met on shared vertices, the atlas split them: the UVs index the split mesh
  // (`vertex_splits`, empty where nothing was split). mesh_with_lightmap applies both.
  std::vector<std::vector<vec2>> lightmap_uvs;
  std::vector<VertexSplit> vertex_splits;
  // Texel edge in metres: the atlas's default (after any growth to fit) and per scene mesh
  // (0 where a mesh has no map). Texel density = 1 / texel edge, texels per metre
  // (texel_density below), the unit Unity and Godot report.
  float texel_size = 0.0f;
  std::vector<float> mesh_texel_size;
  // True only for a map read back from an export made with `--contents all`
  // (gltf_bake_read.h): it holds the direct light too, so renderers must not add their own.
  bool holds_direct_light = false;
  // The map's L1 band per world axis x, y, z (bake/sh_projection.h), W/(sr m^2) per
  // unit of the normal: a bake's with the `directional` setting (the caustic light's, de-ringed,
  // s = 1) or a directional export's read back; else empty.
  std::array<std::vector<vec3>, 3> l1;
  std::vector<float> l1_share;  // with l1: the decode's s per texel
  // Light groups (BakeResult::light_groups): per group, `radiance` from that group's lights
  // alone; they sum to `radiance`. Empty without groups.
  std::vector<std::vector<vec3>> group_radiance;
  IlluminationStats stats;
};

// Texels per metre for a texel edge in metres (0 for 0).
inline float texel_density(float texel_size_m) {
  return texel_size_m > 0.0f ? 1.0f / texel_size_m : 0.0f;
}

// ---- pass 2: radiosity (soft indirect light) ------------------------------------------

struct RadiosityStats {
  uint64_t shots = 0;
  uint64_t rays = 0;                 // rays shot from patches
  uint64_t ray_casts = 0;            // every rtcIntersect call (including specular bounces)
  size_t patch_count = 0;
  vec3 power_emitted{0.0f};          // W
  vec3 residual_unsent{0.0f};        // W, unsent power left at the end
  double residual_fraction = 0.0;    // max channel of residual / emitted
  bool converged = false;
  double seconds = 0.0;
  // Energy bookkeeping (summed in doubles): emitted = absorbed + escaped + residual_unsent.
  vec3 power_absorbed{0.0f};         // W, absorbed by any surface (diffuse 1-R, specular 1-k)
  vec3 power_escaped{0.0f};          // W, left the scene
  uint64_t light_rays = 0;           // rays shot from the lights (first, not counted)
  double setup_seconds = 0.0;        // patches and the BVH over them, part of `seconds`
  vec3 power_received{0.0f};         // W, incident power counted (met >= 2 diffuse surfaces)
};

// The radiosity result of one diffuse scene mesh. `mesh` is the scene mesh refined to the
// patch size (the same surface with more vertices, all attributes interpolated), so that the
// vertex colours can carry the solution; it is what viewers draw in place of the scene mesh.
struct MeshRadiosity {
  Mesh mesh;
  std::vector<vec3> vertex_radiance;      // per vertex of `mesh`, the convention above
  std::vector<uint32_t> triangle_patch;   // per triangle of `mesh`, global patch id
};

struct VertexRadiosity {
  std::vector<MeshRadiosity> meshes;  // per scene mesh; empty `mesh` for non-diffuse meshes
  // Light groups: [group][scene mesh][vertex], each mesh's vertex_radiance from that group's
  // lights alone; they sum to vertex_radiance. Empty without groups.
  std::vector<std::vector<std::vector<vec3>>> group_vertex_radiance;
  RadiosityStats stats;
};

// ---- the soft-light texel map (bake/lightmap/soft_texels.h) ----------------------------

// The radiosity term per node of the illumination atlas, the convention above, made from the
// solution at the end of the bake; renderers draw it in place of vertex radiosity on meshes
// with a lightmap. Empty when the bake has none (no atlas, or a partial bake in the viewer).
struct SoftTexelMap {
  std::vector<vec3> radiance;  // width*height of the illumination atlas, dilated past charts
  std::vector<std::vector<vec3>> group_radiance;  // per light group, as `radiance`; or empty
  uint64_t gather_rays = 0;    // final-gather rays (intersect calls) spent on it
  uint64_t shadow_rays = 0;    // their direct-light shadow rays
  uint64_t distance_rays = 0;  // rays for the filter's proximity radii (soft_texels.h)
  double seconds = 0.0;
  // The map's L1 band per world axis x, y, z (bake/sh_projection.h; bake/lightmap/soft_band.h),
  // W/(sr m^2) per unit of n, de-ringed against `radiance`, s = 0: a bake's with the
  // `directional` setting, else empty. The whole light's only (no per-group bands).
  std::array<std::vector<vec3>, 3> l1;
  uint64_t band_rays = 0;     // the band's gather rays
  double band_seconds = 0.0;  // the band's own work (gather, filter, dilation, de-ringing)
};

// ---- the whole bake ----------------------------------------------------------------------

// Light groups (bake/light_groups.h): a bake of a scene whose lights name groups carries,
// besides the whole light, each group's own light along the same rays (the `group_*` arrays
// above, in the order of `light_groups`); blend_light_groups weighs them into one light.
struct BakeResult {
  IlluminationMaps illumination;
  VertexRadiosity radiosity;
  SoftTexelMap soft_texels;
  uint64_t seed = 0;
  std::vector<std::string> light_groups;  // empty: the scene uses no groups
};

// What renderers consume: the scene with lightmap UVs set and diffuse meshes replaced by
// their radiosity meshes, plus per-mesh per-vertex radiosity (empty where a mesh has none).
struct BakedScene {
  Scene scene;
  std::vector<std::vector<vec3>> vertex_radiance;
  const IlluminationMaps* illumination = nullptr;  // points into the BakeResult
  // True when every illumination-map texel is black (no caustics): lookups are skipped.
  bool illumination_black = false;
  // The maps' L1 bands are decoded at the bumped shading normal (illumination_at, soft_light_at):
  // true when the caustic map or the soft map has one; a renderer may turn it off (render
  // --no-directional).
  bool directional = false;
  // The soft-light texel map (points into the BakeResult), null when the bake has none.
  const std::vector<vec3>* soft_texels = nullptr;
  // Its L1 band (SoftTexelMap::l1), null when the bake has none; decoded (s = 0) at the bumped
  // normal by soft_light_at while `directional` is on.
  const std::array<std::vector<vec3>, 3>* soft_l1 = nullptr;
};

BakedScene make_baked_scene(const Scene& scene, const BakeResult& bake);

// Scene mesh `index` as the illumination maps see it: its vertices split as the atlas split
// them and its lightmap UVs set; the mesh unchanged if it has no map.
Mesh mesh_with_lightmap(const Mesh& mesh, const IlluminationMaps& maps, size_t index);

}  // namespace lb
