// `lightbake info SCENE`: what was loaded: meshes, triangles, materials, lights and their
// power, textures, cameras, bounds. Warnings go to stderr; a broken scene exits with 1.

#include <algorithm>
#include <cstdio>
#include <string>

#include "app/commands.h"
#include "bake/message_line.h"
#include "app/load.h"
#include "bake/bake_result.h"
#include "bake/illumination/atlas_report.h"
#include "bake/light_groups.h"
#include "bake/light_sources.h"
#include "bake/pipeline/bake_settings.h"

namespace lb::app {

namespace {

void print_material(const Scene& scene, const Material& m) {
  const char* colour_name = m.kind == MaterialKind::glass ? "transmittance" : "reflectance";
  std::printf("  %-20s %-8s %s (%.3g, %.3g, %.3g)", m.name.c_str(), to_string(m.kind), colour_name,
              m.reflectance.x, m.reflectance.y, m.reflectance.z);
  if (m.kind == MaterialKind::glass) std::printf(" ior %.3g", m.ior);
  if (m.kind == MaterialKind::glossy) std::printf(" roughness %.3g", m.roughness);
  if (m.reflectance_texture >= 0)
    std::printf(" texture %s", scene.textures[size_t(m.reflectance_texture)].path.c_str());
  if (m.bump != BumpKind::none)
    std::printf(" %s %s scale %.3g", m.bump == BumpKind::height ? "height-map" : "normal-map",
                scene.textures[size_t(m.bump_texture)].path.c_str(), m.bump_scale);
  if (m.is_emitter())
    std::printf(" emits (%.4g, %.4g, %.4g) W/(sr m^2)", m.emission.x, m.emission.y, m.emission.z);
  std::printf("\n");
}

void print_mesh(const Scene& scene, const Mesh& mesh, int name_width) {
  std::printf("  %-*s %7zu triangles %7zu vertices  %8.4g m^2  %s", name_width, mesh.name.c_str(),
              mesh.triangles.size(), mesh.positions.size(), mesh_area(mesh),
              scene.materials[size_t(mesh.material)].name.c_str());
  if (mesh.bake.texel_size > 0)
    std::printf("  lightmap %.4g texels/m", double(texel_density(mesh.bake.texel_size)));
  if (mesh.bake.patch_size > 0) std::printf("  patch %.3g m", mesh.bake.patch_size);
  std::printf("\n");
}

float brightest(vec3 v) {
  return std::max({v.x, v.y, v.z});
}

// Every light with its power in W; lights at infinity count what crosses the scene's bounding
// disk (bake/light_sources.h), so the total compares with the area lights'.
void print_lights(const Scene& scene) {
  const LightSources lights(scene);
  std::printf("lights     %zu\n", lights.size());
  for (size_t i = 0; i < lights.size(); ++i) {
    const vec3 p = lights.power(i);
    switch (lights.kind(i)) {
      case LightKind::area: {
        const AreaLight& light = lights.area_light(i);
        std::printf("  %-28s area %.4g m^2", scene.meshes[size_t(light.mesh)].name.c_str(),
                    light.area);
        if (light.two_sided) std::printf(", both sides");
        break;
      }
      case LightKind::point:
      case LightKind::spot: {
        const Lamp& lamp = lights.lamp(i);
        std::printf("  %-28s %s at (%.3g, %.3g, %.3g), %.4g W/sr (%.4g cd)", lamp.name.c_str(),
                    to_string(lamp.kind), lamp.position.x, lamp.position.y, lamp.position.z,
                    brightest(lamp.intensity), brightest(lamp.intensity) * kLumensPerWatt);
        if (lamp.kind == LampKind::spot)
          std::printf(", cone %.3g..%.3g deg", glm::degrees(lamp.inner_cone),
                      glm::degrees(lamp.outer_cone));
        if (lamp.range > 0.0f) std::printf(", range %.4g m", lamp.range);
        break;
      }
      case LightKind::directional: {
        const Lamp& lamp = lights.lamp(i);
        std::printf("  %-28s directional towards (%.3g, %.3g, %.3g), %.4g W/m^2 (%.4g lx)",
                    lamp.name.c_str(), lamp.direction.x, lamp.direction.y, lamp.direction.z,
                    brightest(lamp.intensity), brightest(lamp.intensity) * kLumensPerWatt);
        break;
      }
      case LightKind::sky:
        std::printf("  %-28s radiance (%.4g, %.4g, %.4g) W/(sr m^2)%s", "sky",
                    scene.sky->radiance.x, scene.sky->radiance.y, scene.sky->radiance.z,
                    scene.sky->texture >= 0 ? " x image" : "");
        break;
    }
    std::printf(", power (%.4g, %.4g, %.4g) W%s\n", p.x, p.y, p.z,
                lights.kind(i) == LightKind::directional || lights.kind(i) == LightKind::sky
                    ? " onto the scene"
                    : "");
  }
  const vec3 total = lights.total_power();
  std::printf("  total power (%.4g, %.4g, %.4g) W\n", total.x, total.y, total.z);
  // Light groups (bake/light_groups.h), only where the scene names any.
  if (light_group_names(scene).empty()) return;
  const std::vector<LightGroupPower> groups = light_group_powers(scene);
  std::printf("light groups %zu (--group-weights NAME=W,...)\n", groups.size());
  for (const LightGroupPower& g : groups)
    std::printf("  %-28s %zu light%s, power (%.4g, %.4g, %.4g) W\n", g.name.c_str(), g.lights,
                g.lights == 1 ? "" : "s", g.power.x, g.power.y, g.power.z);
}

void print_info(const Scene& scene) {
  std::printf("scene      %s\n", scene.source_path.c_str());
  std::printf("meshes     %zu\n", scene.meshes.size());
  size_t name_width = 20;
  for (const Mesh& mesh : scene.meshes) name_width = std::max(name_width, mesh.name.size());
  for (const Mesh& mesh : scene.meshes)
    print_mesh(scene, mesh, int(std::min<size_t>(name_width, 60)));
  std::printf("triangles  %zu\n", triangle_count(scene));
  std::printf("materials  %zu\n", scene.materials.size());
  for (const Material& m : scene.materials) print_material(scene, m);
  std::printf("textures   %zu\n", scene.textures.size());
  for (const Texture& t : scene.textures)
    std::printf("  %-40s %d x %d x %d%s\n", t.path.c_str(), t.width, t.height, t.channels,
                t.srgb_decoded ? " (sRGB decoded)" : "");
  print_lights(scene);
  std::printf("cameras    %zu\n", scene.cameras.size());
  for (const Camera& c : scene.cameras)
    std::printf("  %-20s at (%.3g, %.3g, %.3g) looking at (%.3g, %.3g, %.3g), fov %.3g deg\n",
                c.name.c_str(), c.position.x, c.position.y, c.position.z, c.target.x, c.target.y,
                c.target.z, c.vertical_fov_deg);
  const Bounds bounds = scene_bounds(scene);
  std::printf("bounds     (%.4g, %.4g, %.4g) .. (%.4g, %.4g, %.4g) m\n", bounds.min.x, bounds.min.y,
              bounds.min.z, bounds.max.x, bounds.max.y, bounds.max.z);
  if (scene.world_origin != glm::dvec3(0.0))
    std::printf(
        "centred    far from the file's origin: the bounds above are relative to "
        "(%.17g, %.17g, %.17g) m\n",
        scene.world_origin.x, scene.world_origin.y, scene.world_origin.z);
}

// The lightmap a bake at `texels_per_m` (0: automatic) would lay out, mesh by mesh.
void print_lightmap(const Scene& scene, double texels_per_m, int padding) {
  const LightmapReport report =
      lightmap_report(scene, texels_per_m > 0.0 ? float(1.0 / texels_per_m) : 0.0f, padding);
  std::printf("lightmap   %d x %d texels at %.4g texels/m, %zu on surfaces (%.0f%%), padding %d; "
              "%.2f MiB in an engine (8-bit RGBA with mips), %.2f MiB as half-float EXR\n",
              report.width, report.height, double(report.texels_per_m), report.valid_texels,
              100.0 * double(report.valid_texels) /
                  double(std::max(1, report.width * report.height)),
              padding, double(report.gpu_bytes()) / 1048576.0,
              double(report.half_bytes()) / 1048576.0);
  size_t name_width = 20;
  for (const MeshLightmapRow& row : report.meshes)
    name_width = std::max(name_width, scene.meshes[row.mesh].name.size());
  for (const MeshLightmapRow& row : report.meshes)
    std::printf("  %-*s %7.4g texels/m %5zu charts %8zu texels  UVs %s\n",
                int(std::min<size_t>(name_width, 60)), scene.meshes[row.mesh].name.c_str(),
                double(row.texels_per_m), row.charts, row.texels, row.uvs.c_str());
  for (const std::string& warning : report.warnings)
    print_message("warning", warning);
}

}  // namespace

void register_info(CLI::App& app) {
  auto* cmd = app.add_subcommand("info", "Print what a scene file holds: meshes, lights, bounds");
  auto path = std::make_shared<std::string>();
  cmd->add_option("scene", *path, "Scene file (.toml, .gltf, .glb)")->required();
  auto lightmap = std::make_shared<bool>(false);
  auto density = std::make_shared<double>(0.0);
  auto padding = std::make_shared<int>(3);
  cmd->add_flag("--lightmap", *lightmap,
                "Also lay out the lightmap as a bake would (before the caustic pilot): every "
                "mesh's texels/m, charts, texels, lightmap UVs and their problems, the map's size");
  cmd->add_option("--texel-density", *density,
                  "With --lightmap: texels per metre (default: the scene's [bake] texel_size, "
                  "else the automatic rule)")
      ->check(CLI::Range(0.0, 1e6));
  cmd->add_option("--atlas-padding", *padding, "With --lightmap: texels between charts")
      ->check(CLI::Range(2, 64));
  cmd->callback([path, lightmap, density, padding] {
    const Scene scene = load_or_exit(*path);
    print_info(scene);
    double texels_per_m = *density;
    if (*lightmap && texels_per_m <= 0.0) {
      // The scene's own [bake] texel_size, as a bake of it takes it.
      const float size = resolve_bake_params(scene, BakeSettingsRequest{}).illumination.texel_size;
      if (size > 0.0f) texels_per_m = 1.0 / double(size);
    }
    if (*lightmap) print_lightmap(scene, texels_per_m, *padding);
  });
}

}  // namespace lb::app
