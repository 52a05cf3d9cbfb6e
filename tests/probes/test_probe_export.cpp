// `lightbake export` of a scene with a moving object (docs/light-probes.md, "In the exported
// file"): the object as a node with extras.dynamic and its probe light, the grid as
// scene.extensions.LIGHTBAKE_light_probes, and the file read back with the object moving.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <glm/gtc/constants.hpp>
#include <nlohmann/json.hpp>
#include <string>

#include "bake/accel.h"
#include "bake/io/scene_load.h"
#include "bake/probe_grid.h"
#include "bake/probes/dynamic_light.h"
#include "test_helpers.h"

namespace lb {
namespace {

TEST(ProbeExport, MovingObjectAndGridAreWrittenAndReadBack) {
  const std::string dir = test::fresh_dir("probes", "export");
  const std::string scene = test::source_dir() + "/tests/data/scene/cornell_dynamic.toml";
  const test::CliRun run = test::run_lightbake(
      "export -q '" + scene + "' -o out.gltf --rays-per-zone-side 64 --ray-budget 100000", dir);
  ASSERT_EQ(run.status, 0) << run.err;
  const nlohmann::json file = nlohmann::json::parse(test::read_bytes(dir + "/out.gltf"));

  const auto& grid = file["scenes"][0]["extensions"]["LIGHTBAKE_light_probes"];
  ASSERT_TRUE(grid.is_object());
  // The box is 2 m wide and deep, 2.01 m high (the large block's base is 1 cm below the floor):
  // 16 probes an axis at the centres of equal cells.
  EXPECT_EQ(grid["counts"], nlohmann::json({16, 16, 16}));
  EXPECT_NEAR(grid["spacing"][0].get<double>(), 0.125, 1e-6);
  EXPECT_NEAR(grid["spacing"][1].get<double>(), 2.01 / 16, 1e-6);
  EXPECT_NEAR(grid["origin"][1].get<double>(), -1.01 + 2.01 / 32, 1e-6);
  const size_t probes = 16 * 16 * 16;
  EXPECT_EQ(grid["valid"].size(), probes);
  ASSERT_EQ(grid["coefficients"].size(), 27 * probes);
  const auto used = file["extensionsUsed"];
  EXPECT_NE(std::find(used.begin(), used.end(), "LIGHTBAKE_light_probes"), used.end());

  int moving = 0;
  for (const auto& node : file["nodes"]) {
    if (!node.contains("extras") || !node["extras"].value("dynamic", false)) continue;
    ++moving;
    EXPECT_EQ(node["name"], "ball");
    const auto& sh = node["extras"]["lightbake_probe_sh"];
    ASSERT_EQ(sh.size(), 27u);
    // c_00 of the ball's light: positive in every channel, red above blue (the box's white).
    EXPECT_GT(sh[0].get<double>(), sh[2].get<double>());
    EXPECT_GT(sh[2].get<double>(), 0.0);
    const auto& mesh = file["meshes"][node["mesh"].get<int>()];
    EXPECT_FALSE(mesh["primitives"][0]["attributes"].contains("TEXCOORD_1")) << "no lightmap";
  }
  EXPECT_EQ(moving, 1);

  const LoadResult back = load_scene(dir + "/out.gltf");
  EXPECT_TRUE(back.warnings.empty()) << back.warnings.front();
  ASSERT_EQ(back.scene.dynamic_meshes.size(), 1u);
  EXPECT_EQ(back.scene.dynamic_meshes[0].name, "ball");

  // The file agrees with itself: the ball's numbers are the blend of the file's grid at the
  // ball's centre through the file's static meshes, what an engine blending the grid gets
  // there (tests/web/probe_grid.js does it in three.js). Float rounding apart: the numbers went
  // through JSON as doubles of floats, and the meshes are the file's.
  ProbeGrid read;
  for (int a = 0; a < 3; ++a) {
    read.origin[a] = grid["origin"][a].get<float>();
    read.spacing[a] = grid["spacing"][a].get<float>();
    read.counts[a] = grid["counts"][a].get<int>();
  }
  read.valid = grid["valid"].get<std::vector<uint8_t>>();
  const std::vector<float> numbers = grid["coefficients"].get<std::vector<float>>();
  read.sh.resize(probes);
  for (size_t p = 0; p < probes; ++p)
    for (size_t c = 0; c < size_t(kShCoefficients); ++c)
      read.sh[p][c] = vec3(numbers[27 * p + 3 * c], numbers[27 * p + 3 * c + 1],
                           numbers[27 * p + 3 * c + 2]);
  const Accel accel(back.scene);
  const ProbeBlend blend = blend_probes(read, accel, mesh_centre(back.scene.dynamic_meshes[0]));
  EXPECT_EQ(blend.ring, 0);
  ASSERT_EQ(back.scene.dynamic_meshes[0].probe_sh.size(), size_t(kShCoefficients));
  float largest = 0.0f;
  for (const vec3& c : blend.sh) largest = std::max({largest, std::abs(c.x), std::abs(c.y),
                                                     std::abs(c.z)});
  for (size_t c = 0; c < size_t(kShCoefficients); ++c)
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(back.scene.dynamic_meshes[0].probe_sh[c][k], blend.sh[c][k], 1e-6f * largest)
          << "coefficient " << c << ", channel " << k;

  // The loader read the grid into the scene as the JSON holds it (no root transform here).
  const ProbeGrid& loaded = back.scene.probe_grid;
  ASSERT_EQ(loaded.size(), probes);
  EXPECT_EQ(loaded.counts, read.counts);
  EXPECT_EQ(loaded.origin, read.origin);
  EXPECT_EQ(loaded.spacing, read.spacing);
  EXPECT_EQ(loaded.valid, read.valid);
  for (size_t p = 0; p < probes; ++p) ASSERT_EQ(loaded.sh[p], read.sh[p]) << "probe " << p;

  // The moving mesh's light as the viewer draws it from the file: at each vertex, the library's
  // blend of the JSON's grid at the vertex lifted 1% of the smallest spacing along its normal,
  // E/pi at the normal. Same calls on the same numbers: equal bits.
  const Mesh& ball = back.scene.dynamic_meshes[0];
  const DynamicLight light = light_dynamic_meshes_from_grid(back.scene);
  ASSERT_EQ(light.vertex_light.size(), 1u);
  ASSERT_EQ(light.vertex_light[0].size(), ball.positions.size());
  ASSERT_GT(ball.positions.size(), 100u);
  const float lift = 0.01f * std::min({read.spacing.x, read.spacing.y, read.spacing.z});
  float lowest = 1e30f, highest = 0.0f;
  for (size_t v = 0; v < ball.positions.size(); ++v) {
    const vec3 n = ball.normals[v];
    const vec3 expected =
        sh_irradiance(blend_probes(read, accel, ball.positions[v] + lift * n).sh, n) /
        glm::pi<float>();
    ASSERT_EQ(light.vertex_light[0][v], expected) << "vertex " << v;
    lowest = std::min(lowest, expected.x);
    highest = std::max(highest, expected.x);
  }
  // Not one number for the whole ball: its side towards the box's open front gets well under
  // half of its brightest vertex's light.
  EXPECT_LT(lowest, 0.5f * highest);
  for (size_t c = 0; c < size_t(kShCoefficients); ++c)
    EXPECT_EQ(light.blends[0].sh[c], ball.probe_sh[c]) << "the centre's blend is the node's own";

  // A file without the grid: nothing per vertex (the viewer draws the node's centre blend).
  nlohmann::json without = file;
  without["scenes"][0].erase("extensions");
  std::ofstream(dir + "/no_grid.gltf") << without.dump();
  const LoadResult plain = load_scene(dir + "/no_grid.gltf");
  EXPECT_TRUE(plain.scene.probe_grid.empty());
  ASSERT_EQ(plain.scene.dynamic_meshes.size(), 1u);
  EXPECT_EQ(plain.scene.dynamic_meshes[0].probe_sh.size(), size_t(kShCoefficients));
  EXPECT_TRUE(light_dynamic_meshes_from_grid(plain.scene).vertex_light.empty());

  // The grid is in the root node's frame: moved 1 km with it (the loader then recentres the
  // far scene), the ball takes the same light, float rounding at 1 km apart.
  nlohmann::json far = file;
  nlohmann::json* root = nullptr;
  for (auto& node : far["nodes"])
    if (node.value("name", "") == "lightbake") root = &node;
  ASSERT_NE(root, nullptr);
  (*root)["translation"] = {1000.0, 0.0, 0.0};
  std::ofstream(dir + "/far.gltf") << far.dump();
  const LoadResult moved = load_scene(dir + "/far.gltf");
  EXPECT_EQ(moved.scene.world_origin, glm::dvec3(1000.0, 0.0, 0.0));
  EXPECT_NEAR(moved.scene.probe_grid.origin.x, read.origin.x, 1e-4f);
  const DynamicLight far_light = light_dynamic_meshes_from_grid(moved.scene);
  ASSERT_EQ(far_light.vertex_light.size(), 1u);
  ASSERT_EQ(far_light.vertex_light[0].size(), ball.positions.size());
  double sum = 0.0, far_sum = 0.0;
  for (size_t v = 0; v < ball.positions.size(); ++v) {
    sum += light.vertex_light[0][v].x;
    far_sum += far_light.vertex_light[0][v].x;
  }
  EXPECT_NEAR(far_sum / sum, 1.0, 1e-3);
  // A root that turns the grid cannot keep it aligned with the axes: refused.
  (*root)["rotation"] = {0.0, 0.3826834, 0.0, 0.9238795};
  std::ofstream(dir + "/turned.gltf") << far.dump();
  try {
    load_scene(dir + "/turned.gltf");
    ADD_FAILURE() << "a grid under a turned root was read";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find(
                  "turned.gltf: at scenes[0].extensions.LIGHTBAKE_light_probes: its frame"),
              std::string::npos)
        << e.what();
  }

  // A grid out of shape: one line naming the file and the place.
  nlohmann::json bad = file;
  bad["scenes"][0]["extensions"]["LIGHTBAKE_light_probes"]["valid"][7] = 2;
  std::ofstream(dir + "/bad_grid.gltf") << bad.dump();
  try {
    load_scene(dir + "/bad_grid.gltf");
    ADD_FAILURE() << "a grid with a valid flag of 2 was read";
  } catch (const SceneError& e) {
    EXPECT_EQ(std::string(e.what()),
              dir + "/bad_grid.gltf: at scenes[0].extensions.LIGHTBAKE_light_probes.valid: "
                    "must hold 0 or 1 a probe");
  }
}

}  // namespace
}  // namespace lb
