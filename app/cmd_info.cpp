// `lightbake info SCENE`: what was loaded.

#include <cstdio>
#include <string>

#include "app/commands.h"
#include "app/load.h"
#include "bake/lights.h"

namespace lb::app {

static void print_info(const Scene& scene) {
  std::printf("scene      %s\n", scene.source_path.c_str());
  std::printf("meshes     %zu\n", scene.meshes.size());
  std::printf("triangles  %zu\n", triangle_count(scene));
  std::printf("materials  %zu\n", scene.materials.size());
  for (const Material& m : scene.materials) {
    std::printf("  %-20s %-8s reflectance (%.3g, %.3g, %.3g)", m.name.c_str(), to_string(m.kind),
                m.reflectance.x, m.reflectance.y, m.reflectance.z);
    if (m.kind == MaterialKind::glass) std::printf(" ior %.3g", m.ior);
    if (m.kind == MaterialKind::glossy) std::printf(" roughness %.3g", m.roughness);
    if (m.reflectance_texture >= 0) std::printf(" textured");
    if (m.bump != BumpKind::none) std::printf(" bump");
    if (m.is_emitter())
      std::printf(" emits (%.4g, %.4g, %.4g) W/(sr m^2)", m.emission.x, m.emission.y, m.emission.z);
    std::printf("\n");
  }
  std::printf("textures   %zu\n", scene.textures.size());
  const auto lights = collect_lights(scene);
  std::printf("lights     %zu\n", lights.size());
  for (const AreaLight& light : lights)
    std::printf("  %-20s area %.4g m^2, power (%.4g, %.4g, %.4g) W\n",
                scene.meshes[size_t(light.mesh)].name.c_str(), light.area, light.power.x,
                light.power.y, light.power.z);
  std::printf("cameras    %zu\n", scene.cameras.size());
  const Bounds bounds = scene_bounds(scene);
  std::printf("bounds     (%.4g, %.4g, %.4g) .. (%.4g, %.4g, %.4g) m\n", bounds.min.x, bounds.min.y,
              bounds.min.z, bounds.max.x, bounds.max.y, bounds.max.z);
}

void register_info(CLI::App& app) {
  auto* cmd = app.add_subcommand("info", "Print what a scene file holds: meshes, lights, bounds");
  auto path = std::make_shared<std::string>();
  cmd->add_option("scene", *path, "Scene file (.toml, .gltf, .glb)")->required();
  cmd->callback([path] { print_info(load_or_exit(*path)); });
}

}  // namespace lb::app
