// The one quality knob (bake/quality.h, apply_quality in bake/pipeline/bake.h): what each level
// sets, that it is deterministic, that the scene file and the CLI choose it, and that a bake
// records it. Accuracy per level is charted in docs/speed-accuracy.md ("Quality levels").

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "bake/illumination/atlas.h"
#include "bake/io/scene_load.h"
#include "bake/pipeline/bake.h"
#include "bake/radiosity/patches.h"
#include "test_helpers.h"

namespace lb {
namespace {

namespace fs = std::filesystem;

Scene cornell_box() {
  return load_scene(test::source_dir() + "/scenes/cornell_box.toml").scene;
}

TEST(Quality, StandardIsThePassesOwnDefaults) {
  const Scene scene = cornell_box();
  BakeParams params;
  apply_quality(scene, Quality::standard, params);
  const BakeParams defaults;
  EXPECT_EQ(params.radiosity.patch_size, defaults.radiosity.patch_size);  // automatic
  EXPECT_EQ(params.radiosity.ray_budget, defaults.radiosity.ray_budget);
  EXPECT_EQ(params.illumination.rays_per_zone_side, defaults.illumination.rays_per_zone_side);
  EXPECT_EQ(params.soft_texels.gather_rays, defaults.soft_texels.gather_rays);
  EXPECT_EQ(params.quality, Quality::standard);
}

TEST(Quality, LevelsScaleEveryPassTogetherAndDeterministically) {
  const Scene scene = cornell_box();
  const float automatic = automatic_patch_size(scene);
  const BakeParams defaults;
  // Patches x 1/4, 2, 4: patch edge x 2, 1/sqrt(2), 1/2; rays x 1/4, 4, 16; caustic rays a
  // zone x 1/4, 2, 4 (side x 1/2, sqrt(2), 2); soft-light gather rays 0, x 2, x 4 (of 4);
  // lightmap texels with the caustic rays (edge x 2, 1/sqrt(2), 1/2).
  struct Expected {
    Quality quality;
    float patch_edge;
    uint64_t radiosity_rays;
    int caustic_side;
    int soft_gather_rays;
    float texel_edge;
    int sky_side;
  };
  std::vector<bool> diffuse(scene.meshes.size());
  for (size_t m = 0; m < scene.meshes.size(); ++m)
    diffuse[m] = scene.materials[size_t(scene.meshes[m].material)].is_diffuse();
  const float texel = automatic_texel_size(scene, diffuse, defaults.illumination.atlas_max_size);
  const Expected levels[] = {
      {Quality::draft, 2.0f * automatic, defaults.radiosity.ray_budget / 4, 256, 0, 2.0f * texel,
       4},
      {Quality::high, automatic / std::sqrt(2.0f), defaults.radiosity.ray_budget * 4, 724,
       defaults.soft_texels.gather_rays * 2, texel / std::sqrt(2.0f), 11},
      {Quality::final, automatic / 2.0f, defaults.radiosity.ray_budget * 16, 1024,
       defaults.soft_texels.gather_rays * 4, texel / 2.0f, 16}};
  for (const Expected& e : levels) {
    BakeParams a, b;
    apply_quality(scene, e.quality, a);
    apply_quality(scene, e.quality, b);
    EXPECT_NEAR(a.radiosity.patch_size, e.patch_edge, 1e-6f * e.patch_edge) << to_string(e.quality);
    EXPECT_EQ(a.radiosity.ray_budget, e.radiosity_rays) << to_string(e.quality);
    EXPECT_EQ(a.illumination.rays_per_zone_side, e.caustic_side) << to_string(e.quality);
    EXPECT_EQ(a.soft_texels.gather_rays, e.soft_gather_rays) << to_string(e.quality);
    EXPECT_NEAR(a.illumination.texel_size, e.texel_edge, 1e-6f * e.texel_edge)
        << to_string(e.quality);
    EXPECT_EQ(a.illumination.sky_directions_side, e.sky_side) << to_string(e.quality);
    EXPECT_EQ(a.radiosity.patch_size, b.radiosity.patch_size);  // same bits, every time
    // Everything else is left as it was.
    EXPECT_EQ(a.radiosity.min_rays_per_shot, defaults.radiosity.min_rays_per_shot);
    EXPECT_EQ(a.illumination.feeler_zones, defaults.illumination.feeler_zones);
    EXPECT_EQ(a.seed, defaults.seed);
  }
}

TEST(Quality, NamesRoundTripAndNonsenseIsRefusedByName) {
  for (Quality q : {Quality::draft, Quality::standard, Quality::high, Quality::final})
    EXPECT_EQ(parse_quality(to_string(q)), q);
  try {
    parse_quality("ultra");
    FAIL() << "ultra is no level";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("draft, standard, high or final, not 'ultra'"),
              std::string::npos);
  }
}

// A scene file's `[bake] quality` chooses the level; --quality wins over it; a bake records it.
TEST(QualityCli, SceneFileAndCliChooseTheLevelAndTheManifestRecordsIt) {
  const fs::path dir = test::fresh_dir("quality", "cli");
  {
    std::ofstream scene(dir / "draft_box.toml");
    scene << "include = '" << test::source_dir() << "/scenes/cornell_box.toml'\n"
          << "[bake]\nquality = 'draft'\n";
  }
  const auto settings = [&](const std::string& bake) {
    std::ifstream in(dir / bake / "manifest.json");
    return nlohmann::json::parse(in).at("settings");
  };
  ASSERT_EQ(test::run_lightbake("bake -q draft_box.toml -o from_file", dir.string()).status, 0);
  EXPECT_EQ(settings("from_file").at("quality"), "draft");
  EXPECT_EQ(settings("from_file").at("ray_budget"), 1'000'000);

  ASSERT_EQ(
      test::run_lightbake("bake -q draft_box.toml --quality high -o from_cli", dir.string()).status,
      0);
  EXPECT_EQ(settings("from_cli").at("quality"), "high");
  EXPECT_EQ(settings("from_cli").at("ray_budget"), 16'000'000);

  // A setting given one by one wins over the file's level.
  ASSERT_EQ(test::run_lightbake("bake -q draft_box.toml --ray-budget 200000 -o given", dir.string())
                .status,
            0);
  EXPECT_EQ(settings("given").at("ray_budget"), 200'000);
  EXPECT_EQ(settings("given").at("rays_per_zone_side"), 256);  // the file's

  const test::CliRun both = test::run_lightbake(
      "bake -q draft_box.toml --quality high --ray-budget 5 -o x", dir.string());
  EXPECT_NE(both.status, 0) << "--quality excludes the settings it sets";
  const test::CliRun bad =
      test::run_lightbake("bake -q draft_box.toml --quality ultra -o x", dir.string());
  EXPECT_NE(bad.status, 0);
  EXPECT_NE(bad.err.find("not 'ultra'"), std::string::npos) << bad.err;
  EXPECT_FALSE(fs::exists(dir / "x"));
}

TEST(QualityCli, AnUnknownLevelInTheSceneFileNamesTheKey) {
  const fs::path dir = test::fresh_dir("quality", "bad_file");
  {
    std::ofstream scene(dir / "bad.toml");
    scene << "include = '" << test::source_dir() << "/scenes/cornell_box.toml'\n"
          << "[bake]\nquality = 'best'\n";
  }
  const test::CliRun run = test::run_lightbake("bake -q bad.toml -o b", dir.string());
  EXPECT_NE(run.status, 0);
  EXPECT_NE(run.err.find("bad.toml:3:11: bake.quality: "), std::string::npos) << run.err;
  EXPECT_FALSE(fs::exists(dir / "b"));
}

}  // namespace
}  // namespace lb
