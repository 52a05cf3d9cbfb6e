// Issue 16: the generated level of bench/make_level.py, at its smallest (2 x 2 rooms, 3152
// triangles in the file), loads and bakes at draft, and the bake emits the light power the file
// holds.

#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>

#include "test_helpers.h"

namespace lb {
namespace {

TEST(Level, SmallLevelBakesAndEmitsThePowerTheGeneratorWrote) {
  const std::string dir = test::fresh_dir("level", "small_" + std::to_string(getpid()));
  const test::CliRun made = test::run_command(
      "/usr/bin/python3 '" + test::source_dir() + "/bench/make_level.py' --rooms 2x2 -o small.toml",
      dir);
  ASSERT_EQ(made.status, 0) << made.err;
  // "small.toml: 2 x 2 rooms, 4 lights, ...: N triangles", the count the loader must make.
  std::smatch said;
  ASSERT_TRUE(std::regex_search(made.err, said, std::regex(R"(: (\d+) triangles)"))) << made.err;
  const size_t triangles = std::stoul(said[1]);

  // Each ceiling panel names its material "panelP", P its power in watts (white light).
  std::ifstream file(dir + "/small.toml");
  const std::string text((std::istreambuf_iterator<char>(file)), {});
  const std::regex panel(R"re(material = "panel(\d+)")re");
  double written = 0.0;
  int panels = 0;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), panel);
       it != std::sregex_iterator(); ++it, ++panels)
    written += std::stod((*it)[1]);
  EXPECT_EQ(panels, 4);
  EXPECT_EQ(written, 30.0 + 45.0 + 60.0 + 75.0);  // the first four of make_level's powers

  const test::CliRun bake = test::run_lightbake("bake -q --quality draft small.toml -o bake", dir);
  ASSERT_EQ(bake.status, 0) << bake.err;
  std::ifstream manifest_file(dir + "/bake/manifest.json");
  const nlohmann::json manifest = nlohmann::json::parse(manifest_file);
  // The file's triangles (3152) and the pieces of the floors cut along the walls and the
  // furniture standing on them on load (bake/contact_conform.h): measured 4259.
  const size_t baked = manifest["memory"]["triangles"].get<size_t>();
  EXPECT_GE(baked, triangles);
  EXPECT_LE(baked, triangles + triangles / 2);
  const auto& stats = manifest["radiosity"]["stats"];
  for (int c = 0; c < 3; ++c) {
    const double emitted = stats["power_emitted"][c].get<double>();
    EXPECT_NEAR(emitted, written, 1e-4 * written);  // measured 210.0 W
    // Closed rooms: what is not absorbed is the unsent residual (0.001 of emitted) or died on
    // glass and metal; measured 209.79..209.97 W absorbed.
    const double absorbed = stats["power_absorbed"][c].get<double>();
    EXPECT_LE(absorbed, emitted * (1.0 + 1e-5));
    EXPECT_GE(absorbed, 0.99 * emitted);
  }
}

}  // namespace
}  // namespace lb
