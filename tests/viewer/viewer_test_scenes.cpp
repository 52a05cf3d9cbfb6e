#include "viewer_test_scenes.h"

#include <tbb/parallel_for.h>

#include <cmath>
#include <cstdio>
#include <glm/gtc/constants.hpp>

#include "bake/lights.h"
#include "bake/sampling.h"
#include "bake/surface.h"
#include "test_helpers.h"

namespace lb::test {

Scene make_table_room(float light_size) {
  Scene scene;
  scene.source_path = "table_room (in code)";
  Material wall;
  wall.name = "wall";
  wall.reflectance = vec3(0.7f, 0.68f, 0.62f);
  const int wall_id = add_material(scene, wall);
  Material wood;
  wood.name = "wood";
  wood.reflectance = vec3(0.55f, 0.35f, 0.2f);
  const int wood_id = add_material(scene, wood);
  Material lamp;
  lamp.name = "lamp";
  lamp.reflectance = vec3(0.0f);
  lamp.emission = vec3(12.0f, 11.0f, 9.5f);
  const int lamp_id = add_material(scene, lamp);

  scene.meshes.push_back(make_box({-2, 0, -2}, {2, 3, 2}, wall_id, true, "room"));
  const float h = 0.5f * light_size;
  // Faces down: cross(+x, +z) = -y.
  scene.meshes.push_back(
      make_quad({-h, 2.98f, -h}, {light_size, 0, 0}, {0, 0, light_size}, lamp_id, "light"));
  scene.meshes.push_back(
      make_box({-0.7f, 0.72f, -0.45f}, {0.7f, 0.78f, 0.45f}, wood_id, false, "table top"));
  for (float x : {-0.62f, 0.57f}) {
    for (float z : {-0.37f, 0.32f}) {
      scene.meshes.push_back(
          make_box({x, 0.0f, z}, {x + 0.05f, 0.72f, z + 0.05f}, wood_id, false, "leg"));
    }
  }
  scene.meshes.push_back(make_box({0.9f, 0.0f, 0.6f}, {1.4f, 0.5f, 1.1f}, wall_id, false, "block"));
  Camera camera;
  camera.name = "front";
  camera.position = {1.3f, 1.9f, 1.85f};
  camera.target = {-0.3f, 0.45f, -0.6f};
  camera.vertical_fov_deg = 65.0f;
  scene.cameras.push_back(camera);
  return scene;
}

void add_uniform_field(Scene& scene, float half_size) {
  Material glow;
  glow.reflectance = vec3(0.0f);
  glow.emission = vec3(1.0f);
  scene.meshes.push_back(make_box(vec3(-half_size), vec3(half_size), add_material(scene, glow),
                                  /*inward=*/true, "uniform field"));
}

Ray camera_ray(const ViewCamera& camera, int width, int height, int x, int y) {
  const vec3 forward = camera.forward();
  const vec3 right = glm::normalize(glm::cross(forward, camera.up));
  const vec3 up = glm::cross(right, forward);
  const float tan_half = std::tan(glm::radians(camera.vertical_fov_deg) * 0.5f);
  const float aspect = float(width) / float(height);
  const float ndc_x = 2.0f * (float(x) + 0.5f) / float(width) - 1.0f;
  const float ndc_y = 1.0f - 2.0f * (float(y) + 0.5f) / float(height);
  Ray ray;
  ray.origin = camera.position;
  ray.direction =
      glm::normalize(forward + right * (ndc_x * tan_half * aspect) + up * (ndc_y * tan_half));
  return ray;
}

Image ray_traced_direct(const Scene& scene, const ViewCamera& camera, int width, int height, int n,
                        bool shadows) {
  const Accel accel(scene);
  const std::vector<AreaLight> lights = collect_lights(scene);
  Image image(width, height, 3);
  tbb::parallel_for(0, height, [&](int y) {
    for (int x = 0; x < width; ++x) {
      const Ray ray = camera_ray(camera, width, height, x, y);
      const auto hit = accel.intersect(ray);
      if (!hit) continue;
      const SurfacePoint sp = surface_at(scene, *hit, ray);
      if (!sp.material->is_diffuse()) continue;
      Rng rng(hash_seed(uint64_t(y), uint64_t(x)));
      vec3 sum(0.0f);
      for (const AreaLight& light : lights) {
        vec3 light_sum(0.0f);
        for (int i = 0; i < n; ++i) {
          for (int j = 0; j < n; ++j) {
            const LightSample s = light.sample(scene, stratified(i, j, n, n, rng.next_2d()));
            const vec3 d = s.position - sp.position;
            const float r2 = glm::dot(d, d);
            const vec3 w = d / std::sqrt(r2);
            const float cos_x = glm::dot(sp.shading_normal, w);
            const float cos_l = light.emitting_cosine(s.normal, -w);  // both faces if two-sided
            if (cos_x <= 0.0f || cos_l <= 0.0f) continue;
            if (shadows &&
                accel.occluded(segment_ray(sp.position, sp.geometric_normal, s.position, s.normal)))
              continue;
            light_sum += light.radiance * (cos_x * cos_l / (r2 * s.pdf_area));
          }
        }
        sum += light_sum / float(n * n);
      }
      // E/pi = (1/pi) * integral of L cos cos / r^2 dA, times the reflectance.
      const vec3 value = reflectance_at(scene, sp) * sum / glm::pi<float>();
      for (int c = 0; c < 3; ++c) image.at(x, y, c) = value[c];
    }
  });
  return image;
}

void write_comparison_files(const std::string& name, const Image& image, const Image& reference) {
  const std::string prefix = write_comparison(output_dir(), name, image, reference);
  std::printf("wrote %s{.png,_ref.png,_diff.png,...}\n", prefix.c_str());
}

BakeResult make_constant_bake(const Scene& scene, vec3 radiosity, vec3 caustic) {
  BakeResult bake;
  bake.illumination.width = 4;
  bake.illumination.height = 4;
  bake.illumination.radiance.assign(16, caustic);
  bake.illumination.texel_area.assign(16, 0.01f);
  bake.illumination.valid.assign(16, 1);
  bake.illumination.lightmap_uvs.resize(scene.meshes.size());
  bake.radiosity.meshes.resize(scene.meshes.size());
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    if (!scene.materials[size_t(mesh.material)].is_diffuse()) continue;
    bake.illumination.lightmap_uvs[m].assign(mesh.positions.size(), vec2(0.5f));
    MeshRadiosity& r = bake.radiosity.meshes[m];
    r.mesh = mesh;
    r.mesh.lightmap_uvs = bake.illumination.lightmap_uvs[m];
    r.vertex_radiance.assign(mesh.positions.size(), radiosity);
    for (size_t t = 0; t < mesh.triangles.size(); ++t)
      r.triangle_patch.push_back(uint32_t(1000 * m + t));
  }
  return bake;
}

}  // namespace lb::test
