#include "bake/lights.h"

#include <algorithm>
#include <numbers>

#include "bake/sampling.h"

namespace lb {

std::vector<AreaLight> collect_lights(const Scene& scene) {
  std::vector<AreaLight> lights;
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    const Material& material = scene.materials.at(size_t(mesh.material));
    if (!material.is_emitter()) continue;

    AreaLight light;
    light.mesh = int(m);
    light.radiance = material.emission;
    light.two_sided = material.two_sided_emission;
    double area = 0.0;
    glm::dvec3 centroid(0.0), normal(0.0);
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
      const double a = triangle_area(mesh, t);
      if (!(a > 0.0)) continue;
      const uvec3 tri = mesh.triangles[t];
      const vec3 centre =
          (mesh.positions[tri.x] + mesh.positions[tri.y] + mesh.positions[tri.z]) / 3.0f;
      area += a;
      centroid += a * glm::dvec3(centre);
      const vec3 n = triangle_normal(mesh, t);
      normal += a * glm::dvec3(n);
      light.triangles.push_back(uint32_t(t));
      light.triangle_normals.push_back(n);
      light.triangle_cdf.push_back(float(area));
    }
    if (light.triangles.empty()) continue;
    for (float& c : light.triangle_cdf) c = float(c / area);
    light.triangle_cdf.back() = 1.0f;
    light.area = float(area);
    light.centroid = vec3(centroid / area);
    const double normal_length = glm::length(normal);
    light.normal = normal_length > 0.0 ? vec3(normal / normal_length) : vec3(0.0f, 0.0f, 1.0f);
    // A Lambertian emitter of radiance L and area A sends pi * L * A watts.
    light.power = std::numbers::pi_v<float> * light.radiance * light.area;
    if (light.two_sided) light.power *= 2.0f;
    lights.push_back(std::move(light));
  }
  return lights;
}

LightSample AreaLight::sample(const Scene& scene, vec2 u) const {
  // Pick a triangle by area with u.x, then reuse the remainder of u.x so the sample stays
  // stratified within the chosen triangle.
  const PickedTriangle picked = pick_triangle(triangle_cdf.data(), triangles.size(), u.x);
  const Mesh& mesh = scene.meshes[size_t(this->mesh)];
  const uvec3 tri = mesh.triangles[triangles[picked.index]];
  LightSample s;
  s.position = point_on_triangle(mesh.positions[tri.x], mesh.positions[tri.y],
                                 mesh.positions[tri.z], square_to_triangle({picked.u_x, u.y}));
  s.normal = triangle_normals[picked.index];
  s.pdf_area = 1.0f / area;
  return s;
}

vec3 total_power(const std::vector<AreaLight>& lights) {
  vec3 power(0.0f);
  for (const AreaLight& light : lights) power += light.power;
  return power;
}

}  // namespace lb
