// One binding of the bake's settings (bake/pipeline/bake_settings.h): the table's ranges agree
// with the passes' own checks, the command line of every subcommand that bakes, a scene file's
// [bake] table and a previous bake's manifest (`--like`) all set the same settings by the same
// names, with the documented precedence, and a bake reproduces itself from its directory.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "bake/io/scene_load.h"
#include "bake/pipeline/bake_settings.h"
#include "test_helpers.h"

namespace lb {
namespace {

namespace fs = std::filesystem;

// Settings that keep each bake of the Cornell box well under a CPU second.
const std::string kCheap = "--patch-size 0.25 --ray-budget 200000 --soft-gather-rays 1";

nlohmann::json manifest_settings(const fs::path& bake) {
  std::ifstream in(bake / "manifest.json");
  return nlohmann::json::parse(in).at("settings");
}

std::string file_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(BakeSettings, KeysAndOptionNamesAreUniqueAndDefaultsAreInRange) {
  std::set<std::string> keys, options;
  const BakeParams defaults;
  for (const BakeSetting& setting : bake_settings()) {
    EXPECT_TRUE(keys.insert(setting.key).second) << setting.key;
    EXPECT_TRUE(options.insert(setting.option_name()).second) << setting.key;
    if (setting.is_boolean()) {
      EXPECT_TRUE(options.insert(setting.negative_option_name()).second);
    }
    EXPECT_EQ(setting.check(setting.get(defaults)), "") << setting.key;
    EXPECT_EQ(find_bake_setting(setting.key), &setting);
  }
  EXPECT_EQ(find_bake_setting("no_such_setting"), nullptr);
  EXPECT_EQ(keys.size(), 39u);  // 22 pass-1, 9 radiosity, 7 soft-light settings and the seed
}

// A value the table accepts is never refused by the passes' own checks, and each end of the
// table's range is accepted there.
TEST(BakeSettings, TheTableRangesAgreeWithThePassChecks) {
  const Scene scene = load_scene(test::source_dir() + "/scenes/cornell_box.toml").scene;
  for (const BakeSetting& setting : bake_settings()) {
    for (const double end : {setting.min, setting.max}) {
      if (!std::isfinite(end)) continue;
      BakeParams params;
      // The feeler grid's two sides share one cap: test each end with the other at 1.
      params.illumination.subzones_side = 1;
      params.illumination.feeler_zones = 1;
      setting.set(params, end);
      if (std::string_view(setting.key) == "patch_size" ||
          std::string_view(setting.key) == "ray_budget")
        continue;  // the patch-count estimate and time caps are checked per scene, not here
      EXPECT_NO_THROW(check_illumination_params(params.illumination)) << setting.key << " " << end;
      EXPECT_NO_THROW(check_soft_texel_params(params.soft_texels)) << setting.key << " " << end;
    }
  }
  BakeParams params;
  const BakeSetting& budget = *find_bake_setting("ray_budget");
  EXPECT_THROW(budget.set(params, 0.0), std::invalid_argument);
  EXPECT_THROW(budget.set(params, 2.5), std::invalid_argument);  // not a whole number
  EXPECT_THROW(find_bake_setting("convergence")->set(params, 1.5), std::invalid_argument);
  budget.set(params, 123456.0);
  EXPECT_EQ(params.radiosity.ray_budget, 123456u);
}

// Every command that bakes takes every setting under the same option name (render and view
// seed the bake with their own --seed).
TEST(BakeSettingsCli, EverySubcommandThatBakesTakesEverySetting) {
  for (const std::string command : {"bake", "snapshot", "render", "export", "view"}) {
    const test::CliRun help = test::run_lightbake(command + " --help");
    ASSERT_EQ(help.status, 0) << command;
    for (const BakeSetting& setting : bake_settings()) {
      if (std::string_view(setting.key) == "seed") continue;
      // "--name " for values, "--name,--no-name" for flags; not a longer name's prefix.
      const std::string name = setting.option_name();
      const bool listed = help.out.find(name + " ") != std::string::npos ||
                          help.out.find(name + ",") != std::string::npos;
      EXPECT_TRUE(listed) << command << " lacks " << name;
    }
    for (const char* option : {"--quality", "--like", "--texel-density", "--seed"})
      EXPECT_NE(help.out.find(option), std::string::npos) << command << " lacks " << option;
  }
}

// The command line, a scene file and a previous bake set the same settings; a bake reproduces
// itself from its directory, bit for bit.
TEST(BakeSettingsCli, CommandLineSceneFileAndLikeAgreeAndReproduceTheBake) {
  const fs::path dir = test::fresh_dir("bake_settings", "sources");
  const std::string box = test::source_dir() + "/scenes/cornell_box.toml";
  ASSERT_EQ(test::run_lightbake("bake -q " + box + " -o cli " + kCheap +
                                    " --no-caustic-filter --caustic-max-depth 9 --seed 5",
                                dir.string())
                .status,
            0);
  {
    std::ofstream scene(dir / "keys.toml");
    scene << "include = '" << box << "'\n"
          << "[bake]\npatch_size = 0.25\nray_budget = 200000\nsoft_gather_rays = 1\n"
          << "caustic_filter = false\ncaustic_max_depth = 9\nseed = 5\n";
  }
  ASSERT_EQ(test::run_lightbake("bake -q keys.toml -o file", dir.string()).status, 0);
  ASSERT_EQ(test::run_lightbake("bake -q " + box + " -o like --like cli", dir.string()).status, 0);

  const nlohmann::json cli = manifest_settings(dir / "cli");
  EXPECT_EQ(cli.at("caustic_filter"), false);
  EXPECT_EQ(cli.at("caustic_max_depth"), 9);
  EXPECT_EQ(cli.at("seed"), 5);
  EXPECT_EQ(cli.at("ray_budget"), 200000);
  EXPECT_EQ(manifest_settings(dir / "file"), cli);
  EXPECT_EQ(manifest_settings(dir / "like"), cli);
  for (const char* file : {"radiosity.bin", "illumination.bin"}) {
    EXPECT_EQ(file_bytes(dir / "cli" / file), file_bytes(dir / "file" / file)) << file;
    EXPECT_EQ(file_bytes(dir / "cli" / file), file_bytes(dir / "like" / file)) << file;
  }
  // The seed matters, so equal bits above are not an accident of ignored settings.
  ASSERT_EQ(
      test::run_lightbake("bake -q " + box + " -o seed6 --like cli --seed 6", dir.string()).status,
      0);
  EXPECT_EQ(manifest_settings(dir / "seed6").at("seed"), 6);
  EXPECT_NE(file_bytes(dir / "cli" / "radiosity.bin"), file_bytes(dir / "seed6" / "radiosity.bin"));
}

// Lowest first: defaults, the file's level, the file's keys, the command line's level, its
// keys.
TEST(BakeSettings, PrecedenceFileLevelFileKeysCliLevelCliKeys) {
  Scene scene = load_scene(test::source_dir() + "/scenes/cornell_box.toml").scene;
  scene.quality = Quality::draft;
  scene.bake_settings = {{"ray_budget", 300000.0, "here"}, {"convergence", 0.01, "here"}};
  BakeSettingsRequest request;
  BakeParams params = resolve_bake_params(scene, request);
  EXPECT_EQ(params.quality, Quality::draft);
  EXPECT_EQ(params.radiosity.ray_budget, 300000u);         // the file's key over its level
  EXPECT_EQ(params.illumination.rays_per_zone_side, 256);  // the file's level (draft)
  request.quality = Quality::high;
  params = resolve_bake_params(scene, request);
  EXPECT_EQ(params.radiosity.ray_budget, 16'000'000u);  // the command line's level over the file
  EXPECT_EQ(params.radiosity.convergence, 0.01);        // a key no level sets stays the file's
  request.given = {{find_bake_setting("convergence"), 0.002}};
  params = resolve_bake_params(scene, request);
  EXPECT_EQ(params.radiosity.convergence, 0.002);  // the command line's key over everything
  // A previous bake's settings replace the file's; the command line still wins over them.
  BakeParams previous;
  previous.radiosity.ray_budget = 777;
  previous.quality = Quality::final;
  request = {};
  request.like = previous;
  request.given = {{find_bake_setting("seed"), 9.0}};
  params = resolve_bake_params(scene, request);
  EXPECT_EQ(params.radiosity.ray_budget, 777u);
  EXPECT_EQ(params.radiosity.convergence, BakeParams{}.radiosity.convergence);
  EXPECT_EQ(params.quality, Quality::final);
  EXPECT_EQ(params.seed, 9u);
}

TEST(BakeSettingsCli, BadKeysNameTheFileAndPlaceAndNothingIsWritten) {
  const fs::path dir = test::fresh_dir("bake_settings", "errors");
  const std::string box = test::source_dir() + "/scenes/cornell_box.toml";
  const auto write_scene = [&](const char* name, const std::string& bake_table) {
    std::ofstream scene(dir / name);
    scene << "include = '" << box << "'\n[bake]\n" << bake_table << "\n";
  };
  write_scene("typo.toml", "patch_sise = 0.2");
  write_scene("range.toml", "ray_budget = 0.5");
  write_scene("type.toml", "seed = 'five'");
  const struct {
    const char* scene;
    const char* expected;
  } cases[] = {
      {"typo.toml", "typo.toml:3:14: bake.patch_sise: unknown bake setting"},
      {"range.toml", "range.toml:3:14: bake.ray_budget: 0.5 is outside [1, 1e+11]"},
      {"type.toml", "type.toml:3:8: bake.seed: expected a number, got string"},
  };
  for (const auto& c : cases) {
    const test::CliRun run =
        test::run_lightbake(std::string("bake -q ") + c.scene + " -o out", dir.string());
    EXPECT_EQ(run.status, 1) << c.scene;
    EXPECT_NE(run.err.find(c.expected), std::string::npos) << run.err;
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
  }
  const test::CliRun missing =
      test::run_lightbake("bake -q " + box + " -o out --like no_bake_here", dir.string());
  EXPECT_EQ(missing.status, 1);
  EXPECT_NE(missing.err.find("no_bake_here/manifest.json: cannot open"), std::string::npos)
      << missing.err;
  EXPECT_FALSE(fs::exists(dir / "out"));
}

// `--like` checks a manifest's settings as the command line checks its options: an unknown
// level, a value of the wrong type or out of range, or a seed that differs from the settings'
// is an error naming the manifest and the key, and nothing is baked (issue 42). A manifest
// that says a bake with an atlas has no soft-light map is refused when the bake is read.
TEST(BakeSettingsCli, LikeChecksTheManifestAsTheCommandLineDoes) {
  const fs::path dir = test::fresh_dir("bake_settings", "like_checks");
  const std::string box = test::source_dir() + "/scenes/cornell_box.toml";
  ASSERT_EQ(test::run_lightbake("bake -q " + box + " -o good " + kCheap + " --seed 5",
                                dir.string())
                .status,
            0);
  const nlohmann::json good = [&] {
    std::ifstream in(dir / "good" / "manifest.json");
    return nlohmann::json::parse(in);
  }();
  const struct {
    const char* name;
    const char* pointer;  // the JSON pointer edited
    nlohmann::json value;
    const char* expected;
  } cases[] = {
      {"ultra", "/settings/quality", "ultra",
       "ultra/manifest.json: settings.quality: quality is draft, standard, high or final, not "
       "'ultra'"},
      {"quality_number", "/settings/quality", 2, "settings.quality: expected a string, got number"},
      {"seed_boolean", "/settings/seed", true, "settings.seed: expected a number, got boolean"},
      {"seed_negative", "/settings/seed", -1, "settings.seed: -1 is outside [0, "},
      {"filter_number", "/settings/caustic_filter", 1,
       "settings.caustic_filter: expected true or false, got number"},
      {"seeds_differ", "/seed", 7,
       "seeds_differ/manifest.json: seed: 7 differs from settings.seed 5"},
      // Retired keys (the ray origins are each light's own): only today's value is read.
      {"over_light", "/settings/origins_over_light", true,
       "over_light/manifest.json: settings.origins_over_light: true: no longer a bake setting; "
       "each light chooses where its pass-1 rays start"},
      {"max_angle", "/settings/centre_origin_max_angle", 1e30,
       "settings.centre_origin_max_angle: 1e+30: no longer a bake setting"},
  };
  for (const auto& c : cases) {
    fs::copy(dir / "good", dir / c.name);
    nlohmann::json manifest = good;
    manifest[nlohmann::json::json_pointer(c.pointer)] = c.value;
    std::ofstream(dir / c.name / "manifest.json") << manifest.dump(2);
    const test::CliRun run = test::run_lightbake(
        "bake -q " + box + " -o out --like " + std::string(c.name), dir.string());
    EXPECT_EQ(run.status, 1) << c.name;
    EXPECT_NE(run.err.find(c.expected), std::string::npos) << run.err;
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
    EXPECT_FALSE(fs::exists(dir / "out")) << c.name;
  }

  fs::copy(dir / "good", dir / "no_soft");
  nlohmann::json manifest = good;
  manifest["files"]["soft_light_exr"] = nullptr;
  std::ofstream(dir / "no_soft" / "manifest.json") << manifest.dump(2);
  const test::CliRun render = test::run_lightbake(
      "render -q " + box + " no_soft -o r.exr --size 8x8 --spp 1", dir.string());
  EXPECT_EQ(render.status, 1);
  EXPECT_NE(render.err.find("no_soft/manifest.json: files.soft_light_exr: null, but the bake "
                            "has 'soft_light.exr'"),
            std::string::npos)
      << render.err;
  EXPECT_FALSE(fs::exists(dir / "r.exr"));
}

// A manifest of a build that had the two global origin settings, at the values every bake had
// by default, still bakes again with `--like`, bit for bit; so does a scene file naming them
// at those values. Other values: LikeChecksTheManifestAsTheCommandLineDoes above, and here for a scene file.
TEST(BakeSettingsCli, RetiredOriginKeysAtTodaysValuesAreRead) {
  const fs::path dir = test::fresh_dir("bake_settings", "retired");
  const std::string box = test::source_dir() + "/scenes/cornell_box.toml";
  ASSERT_EQ(test::run_lightbake("bake -q " + box + " -o now " + kCheap,
                                dir.string())
                .status,
            0);
  nlohmann::json manifest = [&] {
    std::ifstream in(dir / "now" / "manifest.json");
    return nlohmann::json::parse(in);
  }();
  EXPECT_FALSE(manifest.at("settings").contains("origins_over_light"));
  manifest["settings"]["origins_over_light"] = false;
  manifest["settings"]["centre_origin_max_angle"] = double(0.05f);  // as it was recorded
  fs::copy(dir / "now", dir / "old");
  std::ofstream(dir / "old" / "manifest.json") << manifest.dump(2);
  const test::CliRun like =
      test::run_lightbake("bake -q " + box + " -o again --like old", dir.string());
  ASSERT_EQ(like.status, 0) << like.err;
  EXPECT_EQ(manifest_settings(dir / "again"), manifest_settings(dir / "now"));
  EXPECT_EQ(file_bytes(dir / "again" / "illumination.bin"),
            file_bytes(dir / "now" / "illumination.bin"));

  Scene scene = load_scene(box).scene;
  scene.bake_settings = {{"centre_origin_max_angle", 0.05, "here"},
                         {"origins_over_light", 0.0, "there"}};
  EXPECT_NO_THROW(resolve_bake_params(scene, BakeSettingsRequest{}));
  scene.bake_settings = {{"origins_over_light", 1.0, "there"}};
  try {
    resolve_bake_params(scene, BakeSettingsRequest{});
    ADD_FAILURE() << "origins_over_light = true was read";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()).rfind("there: true: no longer a bake setting", 0), 0u)
        << e.what();
  }
}

}  // namespace
}  // namespace lb
