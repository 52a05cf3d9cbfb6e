#include "hq_scenes.h"

#include "test_helpers.h"

namespace lb::test {

Scene make_light_grid_room(int per_side) {
  Scene scene;
  Material wall;
  wall.name = "wall";
  wall.reflectance = vec3(0.6f);
  const int wall_material = add_material(scene, wall);
  Material lamp;
  lamp.name = "lamp";
  lamp.reflectance = vec3(0.0f);
  // Keep the total power fixed: nine 0.5 m lights of radiance 5 W/(sr m^2).
  const float size = 0.5f * 3.0f / float(per_side);
  lamp.emission = vec3(5.0f);
  const int lamp_material = add_material(scene, lamp);
  Material wood;
  wood.name = "table";
  wood.reflectance = vec3(0.5f, 0.35f, 0.2f);
  const int table_material = add_material(scene, wood);

  scene.meshes.push_back(make_box({-3, 0, -3}, {3, 3, 3}, wall_material, true, "room"));
  const float spacing = 6.0f / float(per_side);
  for (int i = 0; i < per_side; ++i)
    for (int k = 0; k < per_side; ++k) {
      const float cx = -3.0f + spacing * (float(i) + 0.5f);
      const float cz = -3.0f + spacing * (float(k) + 0.5f);
      // Edges x then z: the quad's front faces -y, down into the room.
      scene.meshes.push_back(make_quad({cx - size / 2, 2.99f, cz - size / 2}, {size, 0, 0},
                                       {0, 0, size}, lamp_material, "lamp"));
    }
  scene.meshes.push_back(make_box({-1, 0.9f, -1}, {1, 1.0f, 1}, table_material, false, "table"));
  Camera camera;
  camera.name = "view";
  camera.position = {0.0f, 1.6f, 2.9f};
  camera.target = {0.0f, 0.6f, -1.0f};
  camera.vertical_fov_deg = 70.0f;
  scene.cameras.push_back(camera);
  return scene;
}

BakedScene unbaked(const Scene& scene) {
  BakedScene baked;
  baked.scene = scene;
  baked.vertex_radiance.resize(scene.meshes.size());
  return baked;
}

}  // namespace lb::test
