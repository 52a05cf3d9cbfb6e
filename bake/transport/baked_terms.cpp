#include "bake/transport/baked_terms.h"

#include <algorithm>
#include <cmath>

#include "bake/bump.h"
#include "bake/sh_projection.h"

namespace lb {

namespace {

// The texels and weights of illumination_map_at's bilinear rule at `lightmap_uv`, texels
// outside every chart (valid(texel) false) left out; the weights are not normalised.
struct Taps {
  size_t texel[4];
  float weight[4];
  int count = 0;
};
template <class Valid>
Taps atlas_taps(const IlluminationMaps& maps, vec2 lightmap_uv, const Valid& valid) {
  const float x = std::clamp(lightmap_uv.x * float(maps.width) - 0.5f, 0.0f, float(maps.width - 1));
  const float y =
      std::clamp(lightmap_uv.y * float(maps.height) - 0.5f, 0.0f, float(maps.height - 1));
  const int i0 = int(x), j0 = int(y);
  const int i1 = std::min(i0 + 1, maps.width - 1), j1 = std::min(j0 + 1, maps.height - 1);
  const float tx = x - float(i0), ty = y - float(j0);
  const int is[4] = {i0, i1, i0, i1};
  const int js[4] = {j0, j0, j1, j1};
  const float ws[4] = {(1 - tx) * (1 - ty), tx * (1 - ty), (1 - tx) * ty, tx * ty};
  Taps taps;
  for (int k = 0; k < 4; ++k) {
    const size_t index = size_t(js[k]) * size_t(maps.width) + size_t(is[k]);
    if (!valid(index)) continue;
    taps.texel[taps.count] = index;
    taps.weight[taps.count++] = ws[k];
  }
  return taps;
}

// Bilinear lookup of an atlas-sized map (illumination_map_at's rule).
vec3 atlas_at(const IlluminationMaps& maps, const std::vector<vec3>& radiance, vec2 lightmap_uv) {
  if (maps.width <= 0 || maps.height <= 0 || radiance.empty()) return vec3(0.0f);
  const bool use_valid = maps.valid.size() == radiance.size();
  const Taps taps =
      atlas_taps(maps, lightmap_uv, [&](size_t k) { return !use_valid || maps.valid[k] != 0; });
  vec3 sum(0.0f);
  float weight = 0.0f;
  for (int k = 0; k < taps.count; ++k) {
    sum += taps.weight[k] * radiance[taps.texel[k]];
    weight += taps.weight[k];
  }
  return weight > 0.0f ? sum / weight : vec3(0.0f);
}

}  // namespace

vec3 illumination_map_at(const IlluminationMaps& maps, vec2 lightmap_uv) {
  return atlas_at(maps, maps.radiance, lightmap_uv);
}

namespace {
// A band's texels read with atlas_at's rule on `maps`' atlas (one set of taps for L0, L1 and
// s): L0 `l0`, L1 `l1`, s `share` (null: s = 0).
ShL1 band_at(const IlluminationMaps& maps, const std::vector<vec3>& l0,
             const std::array<std::vector<vec3>, 3>& l1, const std::vector<float>* share,
             vec2 lightmap_uv) {
  const bool use_valid = maps.valid.size() == l0.size();
  const Taps taps =
      atlas_taps(maps, lightmap_uv, [&](size_t k) { return !use_valid || maps.valid[k] != 0; });
  ShL1 sh;
  float weight = 0.0f;
  for (int k = 0; k < taps.count; ++k) {
    const size_t t = taps.texel[k];
    const float w = taps.weight[k];
    sh.l0 += w * l0[t];
    for (size_t a = 0; a < 3; ++a) sh.l1[a] += w * l1[a][t];
    if (share) sh.share += w * (*share)[t];
    weight += w;
  }
  if (!(weight > 0.0f)) return ShL1{};
  sh.l0 /= weight;
  for (vec3& band : sh.l1) band /= weight;
  sh.share /= weight;
  return sh;
}

bool bumped(const SurfacePoint& sp) {
  return sp.material && sp.material->bump != BumpKind::none;
}
}  // namespace

namespace {
// Barycentric interpolation of per-vertex values of the hit's mesh (0 where it has none).
vec3 interpolated(const BakedScene& baked, const std::vector<std::vector<vec3>>& per_mesh,
                  const SurfacePoint& sp) {
  if (sp.mesh >= per_mesh.size()) return vec3(0.0f);
  const std::vector<vec3>& radiance = per_mesh[sp.mesh];
  if (radiance.empty()) return vec3(0.0f);
  const uvec3 tri = baked.scene.meshes[sp.mesh].triangles[sp.triangle];
  const vec2 b = sp.barycentric;
  return (1.0f - b.x - b.y) * radiance[tri.x] + b.x * radiance[tri.y] + b.y * radiance[tri.z];
}
}  // namespace

vec3 vertex_radiosity_at(const BakedScene& baked, const SurfacePoint& sp) {
  return interpolated(baked, baked.vertex_radiance, sp);
}

vec3 soft_light_at(const BakedScene& baked, const SurfacePoint& sp) {
  if (!baked.soft_texels || !baked.illumination || sp.mesh >= baked.vertex_radiance.size() ||
      baked.vertex_radiance[sp.mesh].empty() || baked.scene.meshes[sp.mesh].lightmap_uvs.empty())
    return vertex_radiosity_at(baked, sp);
  const IlluminationMaps& maps = *baked.illumination;
  // Without a bump map n = n0, where the decode is the map itself: the map's bits.
  if (!baked.directional || !baked.soft_l1 || !bumped(sp))
    return atlas_at(maps, *baked.soft_texels, sp.lightmap_uv);
  // Soft light comes from the whole hemisphere: s = 0 (bake/lightmap/soft_band.h).
  return decode_directional(band_at(maps, *baked.soft_texels, *baked.soft_l1, nullptr,
                                    sp.lightmap_uv),
                            bumped_normal(baked.scene, sp), sp.shading_normal);
}

vec3 illumination_at(const BakedScene& baked, const SurfacePoint& sp) {
  if (!baked.illumination || baked.illumination_black ||
      baked.scene.meshes[sp.mesh].lightmap_uvs.empty())
    return vec3(0.0f);
  const IlluminationMaps& maps = *baked.illumination;
  // Without a bump map n = n0, where the decode is the map itself (to rounding): the map's
  // bits, so a directional bake's other terms (the soft map's gather) keep theirs.
  const bool band = maps.l1[0].size() == maps.radiance.size() &&
                    maps.l1_share.size() == maps.radiance.size();
  if (!baked.directional || !band || maps.width <= 0 || maps.height <= 0 || !bumped(sp))
    return illumination_map_at(maps, sp.lightmap_uv);
  // Where no caustic reaches (every tap's L0 = 0, so its de-ringed L1 = 0 too) the decode is 0:
  // most of a scene's texels, whose bumped normal is then not computed.
  if (const vec3 l0 = illumination_map_at(maps, sp.lightmap_uv); l0 == vec3(0.0f)) return l0;
  return decode_directional(band_at(maps, maps.radiance, maps.l1, &maps.l1_share,
                                    sp.lightmap_uv),
                            bumped_normal(baked.scene, sp), sp.shading_normal);
}

vec3 add_group_terms(const BakedScene& baked, const SurfacePoint& sp, size_t groups,
                     const std::vector<uint32_t>& map_start, const std::vector<vec3>& map_values,
                     const std::vector<std::vector<vec3>>& vertex_radiance, vec3 weight,
                     vec3* out) {
  if (sp.mesh < vertex_radiance.size() && !vertex_radiance[sp.mesh].empty()) {
    const std::vector<vec3>& radiance = vertex_radiance[sp.mesh];
    const uvec3 tri = baked.scene.meshes[sp.mesh].triangles[sp.triangle];
    const vec2 b = sp.barycentric;
    const float b0 = 1.0f - b.x - b.y;
    for (size_t g = 0; g < groups; ++g)
      out[g] += weight * (b0 * radiance[tri.x * groups + g] + b.x * radiance[tri.y * groups + g] +
                          b.y * radiance[tri.z * groups + g]);
  }
  if (map_start.empty() || !baked.illumination ||
      baked.scene.meshes[sp.mesh].lightmap_uvs.empty())
    return vec3(0.0f);
  // atlas_at's rule, every group's texels read together.
  const IlluminationMaps& atlas = *baked.illumination;
  // Outside every chart is in map_start too (one array read, not two).
  const Taps taps = atlas_taps(atlas, sp.lightmap_uv,
                               [&](size_t k) { return map_start[k] != kOffChartGroupTexel; });
  float weight_sum = 0.0f;
  bool lit = false;
  for (int k = 0; k < taps.count; ++k) {
    weight_sum += taps.weight[k];
    lit = lit || map_start[taps.texel[k]] != kNoGroupTexel;
  }
  if (!(weight_sum > 0.0f) || !lit) return vec3(0.0f);
  vec3 total(0.0f);
  for (size_t g = 0; g < groups; ++g) {
    vec3 sum(0.0f);
    for (int k = 0; k < taps.count; ++k)
      if (const uint32_t start = map_start[taps.texel[k]]; start != kNoGroupTexel)
        sum += taps.weight[k] * map_values[start + g];
    out[g] += weight * (sum / weight_sum);
    total += sum / weight_sum;
  }
  return total;
}

}  // namespace lb
