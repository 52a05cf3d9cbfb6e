#include "bake/hq/baked_terms.h"

#include <algorithm>
#include <cmath>

namespace lb {

namespace {

// Bilinear lookup of an atlas-sized map (illumination_map_at's rule).
vec3 atlas_at(const IlluminationMaps& maps, const std::vector<vec3>& radiance, vec2 lightmap_uv) {
  if (maps.width <= 0 || maps.height <= 0 || radiance.empty()) return vec3(0.0f);
  const float x = std::clamp(lightmap_uv.x * float(maps.width) - 0.5f, 0.0f, float(maps.width - 1));
  const float y =
      std::clamp(lightmap_uv.y * float(maps.height) - 0.5f, 0.0f, float(maps.height - 1));
  const int i0 = int(x), j0 = int(y);
  const int i1 = std::min(i0 + 1, maps.width - 1), j1 = std::min(j0 + 1, maps.height - 1);
  const float tx = x - float(i0), ty = y - float(j0);
  const int is[4] = {i0, i1, i0, i1};
  const int js[4] = {j0, j0, j1, j1};
  const float ws[4] = {(1 - tx) * (1 - ty), tx * (1 - ty), (1 - tx) * ty, tx * ty};
  const bool has_valid = maps.valid.size() == radiance.size();
  vec3 sum(0.0f);
  float weight = 0.0f;
  for (int k = 0; k < 4; ++k) {
    const size_t index = size_t(js[k]) * size_t(maps.width) + size_t(is[k]);
    if (has_valid && !maps.valid[index]) continue;
    sum += ws[k] * radiance[index];
    weight += ws[k];
  }
  return weight > 0.0f ? sum / weight : vec3(0.0f);
}

}  // namespace

vec3 illumination_map_at(const IlluminationMaps& maps, vec2 lightmap_uv) {
  return atlas_at(maps, maps.radiance, lightmap_uv);
}

vec3 vertex_radiosity_at(const BakedScene& baked, const SurfacePoint& sp) {
  if (sp.mesh >= baked.vertex_radiance.size()) return vec3(0.0f);
  const std::vector<vec3>& radiance = baked.vertex_radiance[sp.mesh];
  if (radiance.empty()) return vec3(0.0f);
  const uvec3 tri = baked.scene.meshes[sp.mesh].triangles[sp.triangle];
  const vec2 b = sp.barycentric;
  return (1.0f - b.x - b.y) * radiance[tri.x] + b.x * radiance[tri.y] + b.y * radiance[tri.z];
}

vec3 soft_light_at(const BakedScene& baked, const SurfacePoint& sp) {
  if (baked.soft_texels && baked.illumination && sp.mesh < baked.vertex_radiance.size() &&
      !baked.vertex_radiance[sp.mesh].empty() && !baked.scene.meshes[sp.mesh].lightmap_uvs.empty())
    return atlas_at(*baked.illumination, *baked.soft_texels, sp.lightmap_uv);
  return vertex_radiosity_at(baked, sp);
}

vec3 illumination_at(const BakedScene& baked, const SurfacePoint& sp) {
  if (!baked.illumination || baked.illumination_black ||
      baked.scene.meshes[sp.mesh].lightmap_uvs.empty())
    return vec3(0.0f);
  return illumination_map_at(*baked.illumination, sp.lightmap_uv);
}

}  // namespace lb
