#include "viewer/light_table.h"

#include <algorithm>
#include <cmath>

namespace lb {

namespace {

// A buffer texture needs at least one texel to be complete.
gl::BufferTexture upload(std::vector<glm::vec4> texels) {
  if (texels.empty()) texels.emplace_back(0.0f);
  return gl::make_buffer_texture(GL_RGBA32F, texels.data(), texels.size() * sizeof(glm::vec4));
}

}  // namespace

LightTable make_light_table(const GpuScene& scene, const ShadowMaps& shadows,
                            const LampShadowMaps& lamp_shadows) {
  LightTable table;
  const GpuLights& lights = scene.lights();
  std::vector<glm::vec4> texels;
  for (size_t l = 0; l < lights.lights.size(); ++l) {
    const bool shadowed = l < shadows.light_start().size();
    texels.emplace_back(lights.lights[l].radiance, float(lights.outline_start[l]));
    texels.emplace_back(float(lights.triangle_start[l]), float(lights.triangle_count[l]),
                        shadowed ? float(shadows.light_start()[l]) : 0.0f,
                        shadowed ? float(shadows.light_count()[l]) : 0.0f);
    // What the pick weight of shaders/light_pick.glsl needs: a sphere around the light
    // and, for flat lights, the plane.
    const AreaLight& light = lights.lights[l];
    const Mesh& mesh = scene.scene().meshes[size_t(light.mesh)];
    float radius = 0.0f;
    bool planar = true;
    for (size_t k = 0; k < light.triangles.size(); ++k) {
      const uvec3 tri = mesh.triangles[light.triangles[k]];
      for (int c = 0; c < 3; ++c)
        radius = std::max(radius, glm::length(mesh.positions[tri[c]] - light.centroid));
      planar &= glm::dot(light.triangle_normals[k], light.normal) > 0.99999f;
    }
    texels.emplace_back(light.centroid, radius);
    // A two-sided light faces every side: no plane, so the pick weight takes cos_emitter = 1.
    texels.emplace_back(planar && !light.two_sided ? light.normal : vec3(0.0f),
                        luminance(light.radiance) * light.area);
    texels.emplace_back(light.two_sided ? 1.0f : 0.0f, 0.0f, 0.0f, 0.0f);
  }
  table.lights = upload(std::move(texels));
  table.light_count = int(lights.lights.size());

  texels.clear();
  const std::vector<Lamp>& lamps = scene.scene().lights;
  for (size_t l = 0; l < lamps.size(); ++l) {
    const Lamp& lamp = lamps[l];
    const LampShadow shadow =
        l < lamp_shadows.lamps().size() ? lamp_shadows.lamps()[l] : LampShadow{};
    texels.emplace_back(lamp.position, float(int(lamp.kind)));
    texels.emplace_back(glm::normalize(lamp.direction), lamp.range);
    texels.emplace_back(lamp.intensity, std::cos(lamp.inner_cone));
    texels.emplace_back(std::cos(lamp.outer_cone), float(shadow.layer), shadow.cube ? 1.0f : 0.0f,
                        0.0f);
    texels.emplace_back(shadow.range.x, shadow.range.y, shadow.texel.x, shadow.texel.y);
    for (int c = 0; c < 4; ++c) texels.push_back(shadow.matrix[c]);
  }
  table.lamps = upload(std::move(texels));
  table.lamp_count = int(lamps.size());
  gl::check_errors("uploading the light table");
  return table;
}

}  // namespace lb
