#include "bake/bake_result.h"

#include <algorithm>

namespace lb {

BakedScene make_baked_scene(const Scene& scene, const BakeResult& bake) {
  BakedScene baked;
  baked.scene = scene;
  baked.vertex_radiance.resize(scene.meshes.size());
  baked.illumination = &bake.illumination;
  baked.illumination_black =
      std::all_of(bake.illumination.radiance.begin(), bake.illumination.radiance.end(),
                  [](const vec3& texel) { return texel == vec3(0.0f); });
  baked.directional = !bake.illumination.radiance.empty() &&
                     bake.illumination.l1[0].size() == bake.illumination.radiance.size() &&
                     bake.illumination.l1_share.size() == bake.illumination.radiance.size();
  if (!bake.soft_texels.radiance.empty() &&
      bake.soft_texels.radiance.size() ==
          size_t(bake.illumination.width) * size_t(bake.illumination.height)) {
    baked.soft_texels = &bake.soft_texels.radiance;
    if (bake.soft_texels.l1[0].size() == bake.soft_texels.radiance.size() &&
        bake.soft_texels.l1[1].size() == bake.soft_texels.radiance.size() &&
        bake.soft_texels.l1[2].size() == bake.soft_texels.radiance.size()) {
      baked.soft_l1 = &bake.soft_texels.l1;
      baked.directional = true;
    }
  }
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    Mesh& mesh = baked.scene.meshes[m];
    mesh = mesh_with_lightmap(mesh, bake.illumination, m);
    if (m < bake.radiosity.meshes.size() && !bake.radiosity.meshes[m].mesh.positions.empty()) {
      mesh = bake.radiosity.meshes[m].mesh;
      baked.vertex_radiance[m] = bake.radiosity.meshes[m].vertex_radiance;
    }
  }
  return baked;
}

Mesh mesh_with_lightmap(const Mesh& mesh, const IlluminationMaps& maps, size_t index) {
  if (index >= maps.lightmap_uvs.size() || maps.lightmap_uvs[index].empty()) return mesh;
  Mesh out = index < maps.vertex_splits.size() ? split_vertices(mesh, maps.vertex_splits[index])
                                               : mesh;
  if (maps.lightmap_uvs[index].size() == out.positions.size())
    out.lightmap_uvs = maps.lightmap_uvs[index];
  return out;
}

}  // namespace lb
