#pragma once
// The light of a scene's moving objects (Scene::dynamic_meshes) from a bake, as the viewer and
// `snapshot` draw it: each object's probe blend at its bounding box's centre (blend_probes,
// bake/probe_grid.h) over the layout bake_probes would use, and a blend at each of its vertices,
// baking only the probes the blends read. The light across an object changes with position as
// well as direction: on the Cornell box's ball (r = 0.2 m) the side facing the box's opening
// gets E/pi = 0.0059 in HQ mode, the centre's blend 0.0150 there and the vertex's own 0.0094.
// One difference from the grid: the surfaces those probes' rays meet take their direct
// light with the moving objects in the way (their probe rays and the blend's visibility rays
// still see the static scene only), so an object's own shadow on the floor below it darkens
// the light its underside gets. On the Cornell box's ball (r = 0.2 m) that takes its mean
// incident light from +5.8% to -0.8% of HQ's on the ball baked as static geometry
// (tests/probes/test_probes.cpp).

#include <vector>

#include "bake/bake_result.h"
#include "bake/probes/probe_bake.h"

namespace lb {

struct DynamicLight {
  std::vector<ProbeBlend> blends;  // per Scene::dynamic_meshes entry, at its centre
  // Per Scene::dynamic_meshes entry, per vertex: E/pi (W/(sr m^2) per RGB channel) at the
  // vertex's normal from the probes blended at the vertex; empty for a mesh without normals.
  std::vector<std::vector<vec3>> vertex_light;
  size_t probes_baked = 0;
};

// What an export writes for the moving objects (docs/light-probes.md, "In the exported file"):
// the whole grid over the static scene (bake_probes over the baked scene) and each
// Scene::dynamic_meshes entry's blend of that grid at its centre, so that an engine blending
// the file's grid where the object stands gets the node's own numbers. Throws
// std::invalid_argument for bad `params`.
struct ExportProbes {
  ProbeGrid grid;
  std::vector<ShL2> blends;  // per Scene::dynamic_meshes entry
};
ExportProbes bake_export_probes(const Scene& scene, const BakeResult& bake,
                                const ProbeParams& params = {}, const Progress& progress = {});

// The light of a moving object read from an export (Scene::probe_grid, the file's grid): per
// vertex, E/pi at the vertex's normal from blend_probes of the grid at the vertex lifted
// 1% of the smallest spacing along its normal (as light_dynamic_meshes), the visibility rays
// through the scene's static meshes; `blends` the node's own centre blend (Mesh::probe_sh)
// where the file gave one, else the grid's at mesh_centre. Empty when the scene has no grid
// (the file's centre blend alone is drawn then) or no moving object.
DynamicLight light_dynamic_meshes_from_grid(const Scene& scene);

// The per-vertex light of `mesh` (E/pi at each vertex's normal) from `grid`'s probes through
// `accel`, by the rule above; empty for a mesh without normals.
std::vector<vec3> vertex_probe_light(const ProbeGrid& grid, const Accel& accel,
                                     const Mesh& mesh);

// Empty when the scene has no moving object. Throws std::invalid_argument for bad `params`.
DynamicLight light_dynamic_meshes(const Scene& scene, const BakeResult& bake,
                                  const ProbeParams& params = {});

}  // namespace lb
