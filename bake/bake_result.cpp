#include "bake/bake_result.h"

namespace lb {

BakedScene make_baked_scene(const Scene& scene, const BakeResult& bake) {
  BakedScene baked;
  baked.scene = scene;
  baked.vertex_radiance.resize(scene.meshes.size());
  baked.illumination = &bake.illumination;
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    Mesh& mesh = baked.scene.meshes[m];
    if (m < bake.illumination.lightmap_uvs.size() && !bake.illumination.lightmap_uvs[m].empty())
      mesh.lightmap_uvs = bake.illumination.lightmap_uvs[m];
    if (m < bake.radiosity.meshes.size() && !bake.radiosity.meshes[m].mesh.positions.empty()) {
      mesh = bake.radiosity.meshes[m].mesh;
      baked.vertex_radiance[m] = bake.radiosity.meshes[m].vertex_radiance;
    }
  }
  return baked;
}

}  // namespace lb
