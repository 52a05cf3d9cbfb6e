#include "bake/lightmap/unshadowed_light.h"

#include <array>
#include <cmath>

#include <numbers>

namespace lb {

namespace {

// A triangle clipped by up to two planes through the origin has at most 5 corners.
struct Polygon {
  std::array<glm::dvec3, 8> v;
  int n = 0;
};

// Keeps the part of `in` where dot(normal, p) >= 0 (Sutherland-Hodgman on one plane).
Polygon clip(const Polygon& in, const glm::dvec3& normal) {
  Polygon out;
  for (int k = 0; k < in.n; ++k) {
    const glm::dvec3& a = in.v[size_t(k)];
    const glm::dvec3& b = in.v[size_t((k + 1) % in.n)];
    const double da = glm::dot(normal, a), db = glm::dot(normal, b);
    if (da >= 0.0) out.v[size_t(out.n++)] = a;
    if ((da >= 0.0) != (db >= 0.0)) out.v[size_t(out.n++)] = a + (b - a) * (da / (da - db));
  }
  return out;
}

// Lambert's sum for a polygon of corners relative to the receiver: E / L, for unit radiance.
double lambert(const Polygon& p, const glm::dvec3& normal) {
  double sum = 0.0;
  for (int k = 0; k < p.n; ++k) {
    const glm::dvec3& a = p.v[size_t(k)];
    const glm::dvec3& b = p.v[size_t((k + 1) % p.n)];
    const glm::dvec3 c = glm::cross(a, b);
    const double length = glm::length(c);
    if (!(length > 0.0)) continue;
    const double theta = std::atan2(length, glm::dot(a, b));
    sum += theta * glm::dot(normal, c) / length;
  }
  return 0.5 * std::abs(sum);
}

}  // namespace

size_t emitting_triangle_count(const LightSources& sources) {
  size_t count = 0;
  for (const AreaLight& light : sources.area_lights()) count += light.triangles.size();
  return count;
}

vec3 unshadowed_direct(const Scene& scene, const LightSources& sources, const ReceiverPoint& x) {
  const glm::dvec3 position(x.position), geometric(x.geometric_normal), shading(x.shading_normal);
  glm::dvec3 value(0.0);
  for (size_t light = 0; light < sources.size(); ++light) {
    const LightKind kind = sources.kind(light);
    if (kind == LightKind::sky) continue;
    if (kind != LightKind::area) {
      const LightTowards t = sources.sample_towards(light, x.position, vec2(0.5f));
      const float cos_x = glm::dot(x.shading_normal, t.direction);
      if (t.pdf > 0.0f && cos_x > 0.0f && glm::dot(x.geometric_normal, t.direction) > 0.0f)
        value += glm::dvec3(t.radiance) * (double(cos_x) * std::numbers::inv_pi);
      continue;
    }
    const AreaLight& area = sources.area_light(light);
    const Mesh& mesh = scene.meshes[size_t(area.mesh)];
    double unit = 0.0;  // sum of E / (pi L) over the triangles
    for (size_t k = 0; k < area.triangles.size(); ++k) {
      const uvec3 tri = mesh.triangles[area.triangles[k]];
      Polygon p;
      p.n = 3;
      for (int c = 0; c < 3; ++c) p.v[size_t(c)] = glm::dvec3(mesh.positions[tri[c]]) - position;
      // From the side it emits to only (the receiver in front of a one-sided emitter).
      const double front = -glm::dot(glm::dvec3(area.triangle_normals[k]), p.v[0]);
      if (!area.two_sided && !(front > 0.0)) continue;
      p = clip(clip(p, geometric), shading);
      if (p.n >= 3) unit += lambert(p, shading) * std::numbers::inv_pi;
    }
    value += glm::dvec3(area.radiance) * unit;
  }
  return vec3(value);
}

}  // namespace lb
