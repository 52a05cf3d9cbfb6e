#include "bake/probes/dynamic_light.h"

#include <algorithm>
#include <functional>
#include <glm/gtc/constants.hpp>
#include <map>

#include "bake/transport/direct_light.h"
#include "bake/transport/final_gather.h"
#include "bake/light_sources.h"

namespace lb {

ExportProbes bake_export_probes(const Scene& scene, const BakeResult& bake,
                                const ProbeParams& params, const Progress& progress) {
  const BakedScene baked = make_baked_scene(scene, bake);
  const Accel accel(baked.scene);
  const DirectLight direct(baked.scene, accel);
  ExportProbes out;
  out.grid = bake_probes(GatherContext{baked, accel, direct}, params, nullptr, progress);
  for (const Mesh& mesh : scene.dynamic_meshes)
    out.blends.push_back(blend_probes(out.grid, accel, mesh_centre(mesh)).sh);
  return out;
}

namespace {

// A vertex is blended a little off its surface, so that its visibility rays to the probes do
// not start inside a static surface it rests on.
float vertex_lift(const ProbeGrid& layout) {
  return 0.01f * std::min({layout.spacing.x, layout.spacing.y, layout.spacing.z});
}

std::vector<vec3> vertex_light(const ProbeGrid& layout, const Accel& accel, const Mesh& mesh,
                               const std::function<const ShL2*(size_t index)>& probe) {
  std::vector<vec3> out;
  if (mesh.normals.size() != mesh.positions.size()) return out;
  const float lift = vertex_lift(layout);
  out.reserve(mesh.positions.size());
  for (size_t v = 0; v < mesh.positions.size(); ++v) {
    const vec3 n = mesh.normals[v];
    const ProbeBlend blend = blend_probes(layout, accel, mesh.positions[v] + lift * n, probe);
    out.push_back(sh_irradiance(blend.sh, n) / glm::pi<float>());
  }
  return out;
}

}  // namespace

std::vector<vec3> vertex_probe_light(const ProbeGrid& grid, const Accel& accel,
                                     const Mesh& mesh) {
  return vertex_light(grid, accel, mesh, [&](size_t index) -> const ShL2* {
    return grid.valid[index] ? &grid.sh[index] : nullptr;
  });
}

DynamicLight light_dynamic_meshes_from_grid(const Scene& scene) {
  DynamicLight light;
  if (scene.dynamic_meshes.empty() || scene.probe_grid.empty()) return light;
  const Accel accel(scene);  // the static meshes alone: dynamic ones are not in `meshes`
  for (const Mesh& mesh : scene.dynamic_meshes) {
    ProbeBlend centre;
    if (mesh.probe_sh.size() == size_t(kShCoefficients))
      std::copy(mesh.probe_sh.begin(), mesh.probe_sh.end(), centre.sh.begin());
    else
      centre = blend_probes(scene.probe_grid, accel, mesh_centre(mesh));
    light.blends.push_back(centre);
    light.vertex_light.push_back(vertex_probe_light(scene.probe_grid, accel, mesh));
  }
  return light;
}

DynamicLight light_dynamic_meshes(const Scene& scene, const BakeResult& bake,
                                  const ProbeParams& params) {
  DynamicLight light;
  if (scene.dynamic_meshes.empty()) return light;
  check_probe_params(params);
  const BakedScene baked = make_baked_scene(scene, bake);
  const Accel accel(baked.scene);
  // The surfaces a probe's rays meet take their direct light with the moving objects in the
  // way: an object's own shadow on the floor below it darkens the light its underside gets.
  Scene with_movers = baked.scene;
  with_movers.meshes.insert(with_movers.meshes.end(), scene.dynamic_meshes.begin(),
                            scene.dynamic_meshes.end());
  const Accel movers_accel(with_movers);
  const DirectLight shadowed(with_movers, movers_accel);
  const GatherContext context{baked, accel, shadowed};
  const LightSources lights(baked.scene);
  const ProbeGrid layout = probe_layout(baked.scene, params);
  std::map<size_t, ProbeSample> baked_probes;
  const auto probe = [&](size_t index) -> const ShL2* {
    auto it = baked_probes.find(index);
    if (it == baked_probes.end()) {
      const vec3 position = layout.position(layout.cell(index));
      it = baked_probes
               .emplace(index, bake_probe(context, lights, position, params,
                                          probe_stream(params, index)))
               .first;
    }
    return it->second.valid(params) ? &it->second.sh : nullptr;
  };
  for (const Mesh& mesh : scene.dynamic_meshes) {
    light.blends.push_back(blend_probes(layout, accel, mesh_centre(mesh), probe));
    light.vertex_light.push_back(vertex_light(layout, accel, mesh, probe));
  }
  light.probes_baked = baked_probes.size();
  return light;
}

}  // namespace lb
