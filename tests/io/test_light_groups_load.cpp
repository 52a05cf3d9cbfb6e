// Light groups in the scene files (issue 39): `group` on an emissive material, a lamp and the
// sky in TOML, extras.lightbake_group on an emissive material and a lamp's node in glTF; the
// groups' order and power (what `lightbake info` lists), and the weights' one-line errors.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>

#include "bake/io/scene_load.h"
#include "bake/light_groups.h"
#include "blender_style_gltf.h"
#include "test_helpers.h"

namespace lb {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
constexpr double kPi = std::numbers::pi;

// A 4 x 4 m floor, a 1 m^2 panel of 100 W in `day`, a 50 W point lamp in `night`, an
// ungrouped 20 W lamp (`default`) and a sky in `night`.
const char* kScene = R"(
[materials]
panel = { reflectance = 0.0, power = 100, group = "day" }
[[objects]]
shape = "quad"
size = [4, 4]
[[objects]]
name = "panel"
shape = "quad"
size = [1, 1]
normal = [0, -1, 0]
translate = [0, 2, 0]
material = "panel"
[[lights]]
type = "point"
position = [1, 1, 0]
power = 50
group = "night"
[[lights]]
type = "point"
position = [-1, 1, 0]
power = 20
[sky]
radiance = 0.5
group = "night"
)";

fs::path write_scene(const std::string& name, const std::string& text) {
  const fs::path path = fs::path(test::fresh_dir("light_groups_load", name)) / "scene.toml";
  std::ofstream(path) << text;
  return path;
}

TEST(LightGroupsLoad, TomlGroupsInOrderWithTheirPower) {
  const LoadResult r = load_scene(write_scene("toml", kScene).string());
  EXPECT_TRUE(r.warnings.empty());
  EXPECT_EQ(light_group_names(r.scene), (std::vector<std::string>{"day", "night", "default"}));
  const std::vector<LightGroupPower> powers = light_group_powers(r.scene);
  ASSERT_EQ(powers.size(), 3u);
  EXPECT_NEAR(powers[0].power.x, 100.0, 1e-3);  // the panel's power as written
  EXPECT_EQ(powers[0].lights, 1u);
  // The lamp's 50 W and the sky's as LightSources counts it: its radiance integrated over the
  // sphere, 4 pi L, times the scene's bounding disk, pi r^2.
  const BoundingSphere bounds = bounding_sphere(r.scene);
  const double sky = 4.0 * kPi * 0.5 * kPi * double(bounds.radius) * double(bounds.radius);
  EXPECT_NEAR(powers[1].power.x, 50.0 + sky, 1e-3 * (50.0 + sky));
  EXPECT_EQ(powers[1].lights, 2u);
  EXPECT_NEAR(powers[2].power.x, 20.0, 1e-4);
}

TEST(LightGroupsLoad, NoGroupNamedMeansNoGroups) {
  const LoadResult r = load_scene(write_scene("none", R"(
[materials]
panel = { reflectance = 0.0, power = 100 }
[[objects]]
shape = "quad"
material = "panel"
[[lights]]
type = "point"
position = [1, 1, 0]
power = 50
group = "default"
)").string());
  EXPECT_TRUE(light_group_names(r.scene).empty());
  ASSERT_EQ(light_group_powers(r.scene).size(), 1u);
  EXPECT_EQ(light_group_powers(r.scene)[0].name, "default");
}

TEST(LightGroupsLoad, BadGroupNameIsAnErrorNamingItsPlace) {
  try {
    load_scene(write_scene("bad", R"(
[[objects]]
shape = "quad"
[[lights]]
type = "point"
position = [1, 1, 0]
power = 50
group = "a,b"
)").string());
    FAIL() << "loaded";
  } catch (const SceneError& e) {
    EXPECT_THAT(e.what(), HasSubstr("scene.toml:8:"));
    EXPECT_THAT(e.what(), HasSubstr("group"));
  }
}

TEST(LightGroupsLoad, GltfExtrasOnAnEmissiveMaterialAndALampsNode) {
  const fs::path dir = test::fresh_dir("light_groups_load", "gltf");
  const std::string source = test::write_blender_style_gltf(dir.string(), "base", {});
  std::ifstream in(source);
  nlohmann::json document = nlohmann::json::parse(in);
  in.close();
  for (auto& material : document["materials"])
    if (material.contains("emissiveFactor")) material["extras"]["lightbake_group"] = "day";
  for (auto& node : document["nodes"])
    if (node.value("name", "") == "Lamp") node["extras"]["lightbake_group"] = "night";
  const std::string path = (dir / "groups.gltf").string();
  std::ofstream(path) << document.dump();
  const Scene scene = load_scene(path).scene;
  // The panel (day), the lamp (night), the spot without a group (default).
  EXPECT_EQ(light_group_names(scene), (std::vector<std::string>{"day", "night", "default"}));

  for (auto& node : document["nodes"])
    if (node.value("name", "") == "Lamp") node["extras"]["lightbake_group"] = 3;
  std::ofstream(path) << document.dump();
  try {
    load_scene(path);
    FAIL() << "loaded";
  } catch (const SceneError& e) {
    EXPECT_THAT(e.what(), HasSubstr("nodes[2].extras.lightbake_group"));
  }
}

TEST(LightGroupsLoad, WeightsParseAndUnknownNamesAreOneLine) {
  const Scene scene = load_scene(write_scene("weights", kScene).string()).scene;
  const std::vector<std::string> groups = light_group_names(scene);
  EXPECT_EQ(resolve_group_weights(groups, parse_group_weights("night=2,day=0.3"), "s.toml"),
            (std::vector<float>{0.3f, 2.0f, 1.0f}));
  try {
    resolve_group_weights(groups, parse_group_weights("dusk=1"), "s.toml");
    FAIL() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("s.toml has no light group 'dusk'"));
  }
  for (const char* bad : {"day", "day=", "=1", "day=-1", "day=x", "day=1,", "day=inf"})
    EXPECT_THROW(parse_group_weights(bad), std::invalid_argument) << bad;
  // Without groups, `default` weighs the whole light.
  EXPECT_EQ(resolve_group_weights({}, parse_group_weights("default=0.5"), "s.toml"),
            (std::vector<float>{0.5f}));
}

TEST(LightGroupsLoad, ScaledSceneScalesEachGroupsLights) {
  const Scene scene = load_scene(write_scene("scaled", kScene).string()).scene;
  const Scene scaled = scale_light_groups(scene, {0.3f, 2.0f, 0.0f});
  const std::vector<LightGroupPower> before = light_group_powers(scene);
  const LightSources lights(scaled);
  // day x 0.3, night x 2, default off.
  EXPECT_NEAR(lights.total_power().x, 0.3 * before[0].power.x + 2.0 * before[1].power.x,
              1e-4 * before[1].power.x);
}

}  // namespace
}  // namespace lb
