#include "bake/export/gltf_light_groups.h"

#include "bake/light_groups.h"

namespace lb {

std::vector<Lightmap> bake_group_lightmaps(const Scene& scene, const BakeResult& bake,
                                           const LightmapParams& params,
                                           const Progress& progress) {
  std::vector<Lightmap> maps;
  const size_t groups = bake.light_groups.size();
  for (size_t g = 0; g < groups; ++g) {
    std::vector<float> one(groups, 0.0f);
    one[g] = 1.0f;
    maps.push_back(bake_lightmap(scale_light_groups(scene, one), blend_light_groups(bake, one),
                                 params, progress));
  }
  return maps;
}

}  // namespace lb
