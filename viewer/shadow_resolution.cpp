#include "viewer/shadow_resolution.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>
#include <vector>

#include "viewer/lamp_shadow_maps.h"

namespace lb {

namespace {

// Every edge shared by exactly two triangles once vertices are welded by position (meshes
// split their vertices at creases and chart seams, so indices alone would call a box open).
// Sorting, not hashing: 8 bytes an edge and 4 a vertex, whatever the mesh.
bool is_closed(const Mesh& mesh) {
  const std::vector<vec3>& p = mesh.positions;
  // A NaN would break the sort's ordering; the loaders reject them, this keeps it safe anyway.
  auto finite = [](vec3 v) { return std::isfinite(v.x + v.y + v.z); };
  if (!std::all_of(p.begin(), p.end(), finite)) return false;
  std::vector<uint32_t> order(p.size());
  for (size_t v = 0; v < p.size(); ++v) order[v] = uint32_t(v);
  auto before = [&](uint32_t a, uint32_t b) {
    return std::tie(p[a].x, p[a].y, p[a].z) < std::tie(p[b].x, p[b].y, p[b].z);
  };
  std::sort(order.begin(), order.end(), before);
  std::vector<uint32_t> id(p.size());
  uint32_t next = 0;
  for (size_t i = 0; i < order.size(); ++i) {
    if (i > 0 && before(order[i - 1], order[i])) ++next;
    id[order[i]] = next;
  }
  std::vector<uint64_t> edges;
  edges.reserve(3 * mesh.triangles.size());
  for (const uvec3& t : mesh.triangles) {
    for (int e = 0; e < 3; ++e) {
      const uint64_t a = id[t[e]], b = id[t[(e + 1) % 3]];
      if (a != b) edges.push_back(std::min(a, b) << 32 | std::max(a, b));
    }
  }
  if (edges.empty()) return false;
  std::sort(edges.begin(), edges.end());
  for (size_t i = 0; i < edges.size();) {
    size_t j = i;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    if (j - i != 2) return false;
    i = j;
  }
  return true;
}

Bounds mesh_box(const Mesh& mesh) {
  Bounds b;
  for (const vec3& p : mesh.positions) b.extend(p);
  return b;
}

vec3 centre_of(const Bounds& box) { return box.empty() ? vec3(0.0f) : 0.5f * (box.min + box.max); }

constexpr float kOpen = std::numeric_limits<float>::infinity();

// 2 |V| / A as if the mesh were closed (meaningless for an open one: check is_closed). Volume
// by the divergence theorem about `origin`, the box centre (small terms, little cancellation).
float volume_thickness(const Mesh& mesh, vec3 origin) {
  double volume = 0.0, area = 0.0;
  for (const uvec3& t : mesh.triangles) {
    const vec3 a = mesh.positions[t[0]] - origin, b = mesh.positions[t[1]] - origin,
               c = mesh.positions[t[2]] - origin;
    volume += double(glm::dot(a, glm::cross(b, c))) / 6.0;
    area += 0.5 * double(glm::length(glm::cross(b - a, c - a)));
  }
  return area > 0.0 ? float(2.0 * std::abs(volume) / area) : kOpen;
}

// closed_mesh_thickness from the mesh's box and its volume_thickness.
float closed_thickness(const Mesh& mesh, const Bounds& box, float thickness) {
  if (!(thickness < kOpen) || !is_closed(mesh)) return kOpen;
  // A rod's 2 V / A is half its width (a square leg's a / 2, a round one's radius), a
  // slab's its thickness: when the box's thinnest side is within 3 x 2 V / A, the mesh is as
  // thin as its box (a rod or slab along the axes) and that side is what a ray crosses.
  const vec3 extent = box.extent();
  const float thinnest_side = std::min({extent.x, extent.y, extent.z});
  return thinnest_side < 3.0f * thickness ? thinnest_side : thickness;
}

}  // namespace

float closed_mesh_thickness(const Mesh& mesh) {
  const Bounds box = mesh_box(mesh);
  return closed_thickness(mesh, box, volume_thickness(mesh, centre_of(box)));
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
    const Bounds box = mesh_box(mesh);
    const vec3 centre = centre_of(box);
    float nearest = std::numeric_limits<float>::max();
    for (size_t l = 0; l < origins.size(); ++l) {
      nearest = std::min(nearest, fixed_distance[l] > 0.0f ? fixed_distance[l]
                                                           : glm::length(centre - origins[l]));
    }
    // Thinner than this needs more than the minimum. The cheap volume test first: 2 V / A is
    // never more than the width a ray crosses (half of it for a rod), so only meshes below
    // the threshold by it pay for the closedness check (a sort of every edge).
    const float threshold = 2.0f * nearest / (kTexelPerThickness * kMinShadowResolution);
    const float volume_estimate = volume_thickness(mesh, centre);
    if (!(volume_estimate < threshold)) continue;
    const float thickness = closed_thickness(mesh, box, volume_estimate);
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
