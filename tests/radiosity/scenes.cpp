#include "scenes.h"

#include <cmath>
#include <unordered_map>

#include "test_helpers.h"

namespace lb::test {

Scene make_open_scene(bool with_light) {
  Scene scene;
  Material white;
  white.reflectance = vec3(0.7f, 0.5f, 0.3f);
  Material mirror;
  mirror.kind = MaterialKind::mirror;
  mirror.reflectance = vec3(0.9f);
  Material glass;
  glass.kind = MaterialKind::glass;
  glass.reflectance = vec3(0.95f);
  Material metal;
  metal.kind = MaterialKind::glossy;
  metal.roughness = 0.4f;
  metal.reflectance = vec3(0.8f);
  const int w = add_material(scene, white), mi = add_material(scene, mirror),
            g = add_material(scene, glass), me = add_material(scene, metal);
  scene.meshes.push_back(make_quad({-2, 0, -2}, {0, 0, 4}, {4, 0, 0}, w, "floor"));
  scene.meshes.push_back(make_quad({-2, 0, -2}, {4, 0, 0}, {0, 2, 0}, w, "wall"));
  scene.meshes.push_back(make_quad({-2, 0, 2}, {0, 0, -4}, {0, 2, 0}, mi, "mirror"));
  scene.meshes.push_back(make_box({0.5f, 0, 0}, {1.2f, 0.7f, 0.7f}, g, false, "glass"));
  scene.meshes.push_back(make_quad({-1, 0.3f, 0.5f}, {0.8f, 0, 0}, {0, 0.6f, 0.6f}, me, "metal"));
  if (with_light) {
    Material light;
    light.reflectance = vec3(0.5f);
    light.emission = vec3(5.0f, 4.0f, 3.0f);
    const int l = add_material(scene, light);
    scene.meshes.push_back(make_quad({-0.4f, 1.8f, -0.4f}, {0.8f, 0, 0}, {0, 0, 0.8f}, l, "light"));
  }
  return scene;
}

void add_sky_image(Scene& scene) {
  scene.textures.push_back(test::make_rgb_texture(
      8, 4,
      [](int column, int row) {
        const float brightness = row == 1 && column == 5 ? 40.0f : 1.0f + 0.3f * float(column);
        return vec3(brightness, brightness * (0.6f + 0.1f * float(row)),
                    0.5f + 0.1f * float(column));
      },
      "sky.hdr"));
  scene.sky = Sky{vec3(0.5f, 0.6f, 0.8f), int(scene.textures.size()) - 1};
}

// Integral of the vertex radiance (linearly interpolated) over a radiosity mesh, W/sr per
// channel; times pi it is the incident power the mesh received.
glm::dvec3 integrate(const MeshRadiosity& r) {
  glm::dvec3 sum(0.0);
  for (size_t t = 0; t < r.mesh.triangles.size(); ++t) {
    const uvec3 tri = r.mesh.triangles[t];
    sum +=
        double(triangle_area(r.mesh, t)) *
        glm::dvec3(r.vertex_radiance[tri.x] + r.vertex_radiance[tri.y] + r.vertex_radiance[tri.z]) /
        3.0;
  }
  return sum;
}

Scene make_room() {
  Scene scene;
  Material walls;
  walls.name = "walls";
  walls.reflectance = vec3(0.75f);
  Material block = walls;
  block.name = "block";
  block.reflectance = vec3(0.6f, 0.5f, 0.4f);
  Material light = walls;
  light.name = "light";
  light.reflectance = vec3(0.8f);
  light.emission = vec3(10.0f);
  const int w = add_material(scene, walls), b = add_material(scene, block),
            l = add_material(scene, light);
  scene.meshes.push_back(make_box({0, 0, 0}, {4, 3, 4}, w, true, "room"));
  scene.meshes.push_back(make_box({1.2f, 0, 1.5f}, {2.2f, 1.2f, 2.5f}, b, false, "block"));
  // Front = cross(x, z) = -y: facing down.
  scene.meshes.push_back(make_quad({1.5f, 2.99f, 1.5f}, {1, 0, 0}, {0, 0, 1}, l, "light"));
  return scene;
}

Scene make_room_with_mirror() {
  Scene scene = make_room();
  Material mirror;
  mirror.kind = MaterialKind::mirror;
  mirror.reflectance = vec3(0.9f);
  const int m = add_material(scene, mirror);
  scene.meshes.push_back(make_quad({3.98f, 0.5f, 1.0f}, {0, 0, 2}, {0, 2, 0}, m, "mirror"));
  scene.meshes.push_back(make_sphere({3.0f, 0.4f, 2.0f}, 0.35f, 12, 24, 0, false, "ball"));
  scene.source_path = "room-in-code";
  return scene;
}

std::map<std::pair<std::array<float, 3>, std::array<float, 3>>, int> edge_uses(const Mesh& mesh) {
  std::map<std::pair<std::array<float, 3>, std::array<float, 3>>, int> uses;
  auto key = [&](uint32_t v) {
    const vec3 p = glm::round(mesh.positions[v] * 1e6f) + 0.0f;
    return std::array<float, 3>{p.x, p.y, p.z};
  };
  for (const uvec3& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) {
      auto a = key(t[k]), b = key(t[(k + 1) % 3]);
      if (b < a) std::swap(a, b);
      ++uses[{a, b}];
    }
  return uses;
}

Mesh extract_triangles(const Mesh& mesh, const std::function<bool(size_t)>& keep) {
  Mesh out;
  out.name = mesh.name;
  out.material = mesh.material;
  out.bake = mesh.bake;
  std::unordered_map<uint32_t, uint32_t> remap;
  auto vertex = [&](uint32_t v) {
    auto [it, inserted] = remap.try_emplace(v, uint32_t(out.positions.size()));
    if (inserted) {
      out.positions.push_back(mesh.positions[v]);
      if (!mesh.normals.empty()) out.normals.push_back(mesh.normals[v]);
      if (!mesh.uvs.empty()) out.uvs.push_back(mesh.uvs[v]);
    }
    return it->second;
  };
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (!keep(t)) continue;
    const uvec3 tri = mesh.triangles[t];
    out.triangles.push_back({vertex(tri.x), vertex(tri.y), vertex(tri.z)});
  }
  return out;
}

Scene make_emitting_sphere(float rho, float emission, float cap_degrees, int rings, int segments) {
  Scene scene;
  Material wall;
  wall.name = "wall";
  wall.reflectance = vec3(rho);
  Material cap = wall;
  cap.name = "cap";
  cap.emission = vec3(emission);
  const int w = add_material(scene, wall), c = add_material(scene, cap);
  const Mesh sphere = make_sphere({0, 0, 0}, 1.0f, rings, segments, w, true, "sphere");
  const float cap_y = std::cos(cap_degrees * 3.14159265f / 180.0f);
  auto in_cap = [&](size_t t) {
    const uvec3 tri = sphere.triangles[t];
    const float y =
        (sphere.positions[tri.x].y + sphere.positions[tri.y].y + sphere.positions[tri.z].y) / 3.0f;
    return y > cap_y;
  };
  scene.meshes.push_back(extract_triangles(sphere, [&](size_t t) { return !in_cap(t); }));
  Mesh cap_mesh = extract_triangles(sphere, in_cap);
  cap_mesh.material = c;
  cap_mesh.name = "cap";
  scene.meshes.push_back(cap_mesh);
  return scene;
}

}  // namespace lb::test
