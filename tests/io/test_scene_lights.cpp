// Lamps and the sky in the TOML format: each strength key's unit (W, W/sr, cd; W/m^2, lx at
// 683 lm/W), directions, cones, ranges, the sky's image, includes, and one-line errors.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <numbers>

#include "bake/io/image_io.h"
#include "bake/io/scene_load.h"
#include "bake/light_sources.h"
#include "test_helpers.h"

namespace lb {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
constexpr double kPi = std::numbers::pi;

const char* kFloor = R"(
[[objects]]
shape = "quad"
size = [4, 4]
)";

fs::path dir_for_test() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  return test::fresh_dir("scene_lights", info->name());
}

LoadResult load_text(const std::string& toml) {
  const fs::path path = dir_for_test() / "scene.toml";
  std::ofstream(path) << kFloor << toml;
  return load_scene(path.string());
}

std::string load_error(const std::string& toml) {
  try {
    load_text(toml);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "(loaded)";
}

TEST(SceneLights, PointLampStrengthsAndTheirUnits) {
  const LoadResult r = load_text(R"(
[[lights]]
name = "bulb"
type = "point"
position = [0, 2, 0]
power = 100
colour = [1, 0.5, 0.25]
[[lights]]
type = "point"
position = [1, 2, 0]
intensity = 3
range = 5
[[lights]]
type = "point"
position = [2, 2, 0]
candela = 683
)");
  EXPECT_TRUE(r.warnings.empty()) << r.warnings.front();
  const auto& lights = r.scene.lights;
  ASSERT_EQ(lights.size(), 3u);
  EXPECT_EQ(lights[0].name, "bulb");
  EXPECT_EQ(lights[0].kind, LampKind::point);
  // A point lamp of P W sends P / (4 pi) W/sr every way.
  EXPECT_NEAR(lights[0].intensity.x, 100.0 / (4.0 * kPi), 1e-5);
  EXPECT_NEAR(lights[0].intensity.z, 25.0 / (4.0 * kPi), 1e-5);
  EXPECT_EQ(lights[0].position, vec3(0, 2, 0));
  EXPECT_EQ(lights[1].name, "light1");
  EXPECT_FLOAT_EQ(lights[1].intensity.y, 3.0f);
  EXPECT_FLOAT_EQ(lights[1].range, 5.0f);
  EXPECT_FLOAT_EQ(lights[2].intensity.x, 1.0f);  // 683 cd = 1 W/sr
  // And the power the passes see: 4 pi I.
  const LightSources sources(r.scene);
  EXPECT_NEAR(sources.power(0).x, 100.0, 1e-3);
}

TEST(SceneLights, SpotAndSunDirectionsConesAndUnits) {
  const LoadResult r = load_text(R"(
[[lights]]
type = "spot"
position = [0, 3, 0]
target = [0, 0, 1]
inner_angle = 20
outer_angle = 30
power = 40
[[lights]]
type = "sun"
direction = [0, -2, 0]
lux = 68300
[[lights]]
type = "directional"
direction = [1, -1, 0]
irradiance = [2, 3, 4]
)");
  ASSERT_EQ(r.scene.lights.size(), 3u);
  const Lamp& spot = r.scene.lights[0];
  EXPECT_EQ(spot.kind, LampKind::spot);
  EXPECT_NEAR(glm::length(spot.direction - glm::normalize(vec3(0, -3, 1))), 0.0f, 1e-6f);
  EXPECT_NEAR(spot.inner_cone, 20.0 * kPi / 180.0, 1e-6);
  EXPECT_NEAR(spot.outer_cone, 30.0 * kPi / 180.0, 1e-6);
  // Blender's convention: a spot's power is given as if it were a point lamp.
  EXPECT_NEAR(spot.intensity.x, 40.0 / (4.0 * kPi), 1e-5);
  const Lamp& sun = r.scene.lights[1];
  EXPECT_EQ(sun.kind, LampKind::directional);
  EXPECT_EQ(sun.direction, vec3(0, -1, 0));
  EXPECT_NEAR(sun.intensity.x, 100.0, 1e-3);  // 68300 lx = 100 W/m^2
  EXPECT_NEAR(r.scene.lights[2].intensity.z, 4.0f, 1e-6f);
  EXPECT_NEAR(r.scene.lights[2].direction.x, std::sqrt(0.5f), 1e-6f);
}

TEST(SceneLights, SkyRadianceAndImage) {
  const fs::path dir = dir_for_test();
  Image image;
  image.width = 8;
  image.height = 4;
  image.channels = 3;
  image.pixels.assign(8 * 4 * 3, 0.5f);
  write_image((dir / "sky.exr").string(), image);
  std::ofstream(dir / "scene.toml") << kFloor << R"(
[sky]
image = "sky.exr"
radiance = 2
)";
  const LoadResult r = load_scene((dir / "scene.toml").string());
  ASSERT_TRUE(r.scene.sky.has_value());
  EXPECT_EQ(r.scene.sky->radiance, vec3(2.0f));
  ASSERT_GE(r.scene.sky->texture, 0);
  const Texture& texture = r.scene.textures[size_t(r.scene.sky->texture)];
  EXPECT_EQ(texture.width, 8);
  EXPECT_FALSE(texture.srgb_decoded);
  const LightSources sources(r.scene);
  ASSERT_EQ(sources.size(), 1u);
  // A uniform image of 0.5 times 2: radiance 1 everywhere, 4 pi over the sphere.
  EXPECT_NEAR(sources.sky()->integral().x, 4.0 * kPi, 1e-3);
}

TEST(SceneLights, IncludedLightsAreReplacedByName) {
  const fs::path dir = dir_for_test();
  std::ofstream(dir / "base.toml") << kFloor << R"(
[[lights]]
name = "key"
type = "point"
position = [0, 2, 0]
intensity = 1
[[lights]]
name = "fill"
type = "point"
position = [1, 2, 0]
intensity = 1
[sky]
radiance = 0.1
)";
  std::ofstream(dir / "scene.toml") << R"(
include = "base.toml"
[[lights]]
name = "key"
type = "point"
position = [0, 3, 0]
intensity = 5
)";
  const LoadResult r = load_scene((dir / "scene.toml").string());
  ASSERT_EQ(r.scene.lights.size(), 2u);
  EXPECT_EQ(r.scene.lights[0].name, "key");
  EXPECT_FLOAT_EQ(r.scene.lights[0].intensity.x, 5.0f);
  EXPECT_EQ(r.scene.lights[1].name, "fill");
  ASSERT_TRUE(r.scene.sky.has_value());
  EXPECT_EQ(r.scene.sky->radiance, vec3(0.1f));
}

TEST(SceneLights, BadLightsAreOneLineErrorsWithTheirPlace) {
  EXPECT_THAT(load_error("[[lights]]\ntype = \"point\"\nposition = [0, 1, 0]\npower = 1\n"
                         "intensity = 2\n"),
              HasSubstr("scene.toml:8:9: lights[0].power: give one of its strengths, not both "
                        "'lights[0].intensity' and 'lights[0].power'"));
  EXPECT_THAT(load_error("[[lights]]\ntype = \"area\"\n"),
              HasSubstr("lights[0].type: unknown light type 'area' (expected point, spot or "
                        "directional)"));
  EXPECT_THAT(load_error("[[lights]]\ntype = \"spot\"\nposition = [0, 1, 0]\npower = 1\n"),
              HasSubstr("lights[0]: a spot light needs 'direction' or 'target'"));
  EXPECT_THAT(load_error("[[lights]]\ntype = \"spot\"\nposition = [0, 1, 0]\npower = 1\n"
                         "direction = [0, -1, 0]\ninner_angle = 40\nouter_angle = 30\n"),
              HasSubstr("lights[0].outer_angle: spot angles need 0 <= inner_angle < outer_angle "
                        "<= 90 degrees, got 40 and 30"));
  EXPECT_THAT(load_error("[[lights]]\ntype = \"sun\"\ndirection = [0, 0, 0]\nirradiance = 1\n"),
              HasSubstr("lights[0].direction: the light's direction has zero length"));
  EXPECT_THAT(load_error("[[lights]]\ntype = \"point\"\nposition = [0, 1, 0]\n"),
              HasSubstr("a point light needs 'power' (W), 'intensity' (W/sr) or 'candela'"));
  EXPECT_THAT(load_error("[[lights]]\ntype = \"point\"\nposition = [0, 1, 0]\npower = -1\n"),
              HasSubstr("lights[0].power: must not be negative"));
  EXPECT_THAT(load_error("[sky]\nradiance = [1, -1, 1]\n"),
              HasSubstr("sky.radiance: sky radiance must not be negative"));
}

TEST(SceneLights, ALampAloneLightsTheSceneWithoutTheNothingEmitsWarning) {
  const LoadResult lit =
      load_text("[[lights]]\ntype = \"point\"\nposition = [0, 1, 0]\npower = 1\n");
  EXPECT_TRUE(lit.warnings.empty());
  const LoadResult dark = load_text("");
  ASSERT_EQ(dark.warnings.size(), 1u);
  EXPECT_THAT(dark.warnings[0], HasSubstr("nothing emits light"));
}

}  // namespace
}  // namespace lb
