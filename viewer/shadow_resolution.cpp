#include "viewer/shadow_resolution.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <unordered_map>

#include "viewer/lamp_shadow_maps.h"

namespace lb {

namespace {

struct PositionHash {
  size_t operator()(const vec3& p) const {
    auto bits = [](float f) {
      uint32_t u;
      std::memcpy(&u, &f, sizeof u);
      return uint64_t(u);
    };
    return size_t((bits(p.x) * 0x9E3779B97F4A7C15ull) ^ (bits(p.y) * 0xC2B2AE3D27D4EB4Full) ^
                  (bits(p.z) * 0x165667B19E3779F9ull));
  }
};

// Every edge shared by exactly two triangles once vertices are welded by position (meshes
// split their vertices at creases and chart seams, so indices alone would call a box open).
bool is_closed(const Mesh& mesh) {
  std::unordered_map<vec3, uint32_t, PositionHash> welded;
  std::vector<uint32_t> id(mesh.positions.size());
  for (size_t v = 0; v < mesh.positions.size(); ++v)
    id[v] = welded.emplace(mesh.positions[v], uint32_t(welded.size())).first->second;
  std::unordered_map<uint64_t, int> edges;
  for (const uvec3& t : mesh.triangles) {
    for (int e = 0; e < 3; ++e) {
      const uint64_t a = id[t[e]], b = id[t[(e + 1) % 3]];
      if (a == b) continue;
      ++edges[std::min(a, b) << 32 | std::max(a, b)];
    }
  }
  return !edges.empty() &&
         std::all_of(edges.begin(), edges.end(), [](const auto& e) { return e.second == 2; });
}

Bounds mesh_box(const Mesh& mesh) {
  Bounds b;
  for (const vec3& p : mesh.positions) b.extend(p);
  return b;
}

vec3 box_centre(const Mesh& mesh) {
  const Bounds b = mesh_box(mesh);
  return b.empty() ? vec3(0.0f) : 0.5f * (b.min + b.max);
}

constexpr float kOpen = std::numeric_limits<float>::infinity();

// 2 |V| / A as if the mesh were closed (meaningless for an open one: check is_closed).
float volume_thickness(const Mesh& mesh) {
  // Volume by the divergence theorem about the box centre (small terms, little cancellation).
  const vec3 o = box_centre(mesh);
  double volume = 0.0, area = 0.0;
  for (const uvec3& t : mesh.triangles) {
    const vec3 a = mesh.positions[t[0]] - o, b = mesh.positions[t[1]] - o,
               c = mesh.positions[t[2]] - o;
    volume += double(glm::dot(a, glm::cross(b, c))) / 6.0;
    area += 0.5 * double(glm::length(glm::cross(b - a, c - a)));
  }
  return area > 0.0 ? float(2.0 * std::abs(volume) / area) : kOpen;
}

}  // namespace

float closed_mesh_thickness(const Mesh& mesh) {
  const float thickness = volume_thickness(mesh);
  if (!(thickness < kOpen) || !is_closed(mesh)) return kOpen;
  // A rod's 2 V / A is half its width (a square leg's a / 2, a round one's radius), a
  // slab's its thickness: when the box's thinnest side is within 3 x 2 V / A, the mesh is as
  // thin as its box (a rod or slab along the axes) and that side is what a ray crosses.
  const vec3 extent = mesh_box(mesh).extent();
  const float thinnest_side = std::min({extent.x, extent.y, extent.z});
  return thinnest_side < 3.0f * thickness ? thinnest_side : thickness;
}

ShadowResolution automatic_shadow_resolution(const Scene& scene,
                                             const std::vector<AreaLight>& lights, int layers) {
  // Where each light's maps are centred: area lights' cubes over their surface, point and
  // spot lamps at their position; a directional lamp's map spans the scene's bounding sphere,
  // as a point's cube would at its radius.
  std::vector<vec3> origins;
  std::vector<float> fixed_distance;  // > 0: the texel's distance regardless of the caster
  for (const AreaLight& light : lights) {
    origins.push_back(light.centroid);
    fixed_distance.push_back(0.0f);
  }
  const float radius = 0.505f * std::max(scene_bounds(scene).diagonal(), 1e-3f);
  int lamps = 0;
  for (const Lamp& lamp : scene.lights) {
    if (lamps++ == kMaxShadowedLamps) break;
    origins.push_back(lamp.position);
    fixed_distance.push_back(lamp.kind == LampKind::directional ? radius : 0.0f);
  }

  ShadowResolution choice;
  float needed = 0.0f;
  for (const Mesh& mesh : scene.meshes) {
    if (origins.empty()) break;
    // Emitters cast no shadow; glass does in the raster view, but what lies under it gets
    // its light from the caustic maps, not the direct term.
    const Material& material = scene.materials[size_t(mesh.material)];
    if (material.is_emitter() || material.kind == MaterialKind::glass) continue;
    // The nearest light: it usually lights the caster's foot most, and a far light's texels
    // there would make every small object in a wide level "thin".
    const vec3 centre = box_centre(mesh);
    float nearest = std::numeric_limits<float>::max();
    for (size_t l = 0; l < origins.size(); ++l) {
      nearest = std::min(nearest, fixed_distance[l] > 0.0f ? fixed_distance[l]
                                                           : glm::length(centre - origins[l]));
    }
    // Thinner than this needs more than the minimum. The cheap volume test first: 2 V / A is
    // never more than the width a ray crosses (half of it for a rod), so only meshes below
    // the threshold by it pay for the closedness check (a hash of every edge).
    const float threshold = 2.0f * nearest / (kTexelPerThickness * kMinShadowResolution);
    if (!(volume_thickness(mesh) < threshold)) continue;
    const float thickness = closed_mesh_thickness(mesh);
    if (!(thickness < threshold)) continue;
    const float need = 2.0f * nearest / (kTexelPerThickness * std::max(thickness, 1e-6f));
    if (need > needed) {
      needed = need;
      choice.caster = mesh.name;
      choice.thickness = thickness;
      choice.distance = nearest;
    }
  }
  if (choice.caster.empty()) return choice;
  constexpr int kStep = 256;
  const int wanted = int(std::min(std::ceil(needed / kStep), 4096.0f / kStep)) * kStep;
  const double per_texel = 4.0 * std::max(layers, 1);
  const int affordable = int(std::sqrt(kShadowMemoryBudget / per_texel)) / kStep * kStep;
  choice.resolution = std::max(kMinShadowResolution, std::min(wanted, affordable));
  choice.capped = wanted > affordable;
  return choice;
}

}  // namespace lb
