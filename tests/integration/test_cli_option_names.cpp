// One name per concept across subcommands (docs/command-line.md, "One name per concept"): the
// old spellings still work as hidden aliases that print one deprecation line.

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include "test_helpers.h"

namespace lb {
namespace {

namespace fs = std::filesystem;

int count_lines_with(const std::string& text, const std::string& what) {
  int count = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++count;
  return count;
}

// `snapshot ... OPTIONS -o NAME` of the Cornell box, direct light only, 80 x 60.
test::CliRun snapshot(const fs::path& dir, const std::string& options, const std::string& name) {
  std::string args = "snapshot '";
  args += test::source_dir();
  args += "/scenes/cornell_box.toml' --no-bake --size 80x60 -q " + options + " -o " + name;
  return test::run_lightbake(args, dir.string());
}

TEST(OptionNames, OldSnapshotSpellingsDrawTheSameImageWithOneNoteEach) {
  const fs::path dir = test::fresh_dir("option_names", "snapshot");
  const test::CliRun old = snapshot(dir, "--curve clamp --term radiosity", "old.png");
  const test::CliRun now = snapshot(dir, "--tone clamp --terms radiosity", "new.png");
  const test::CliRun plain = snapshot(dir, "", "default.png");
  ASSERT_EQ(old.status, 0) << old.err;
  ASSERT_EQ(now.status, 0) << now.err;
  ASSERT_EQ(plain.status, 0) << plain.err;
  const std::string image = test::read_bytes(dir / "old.png");
  EXPECT_FALSE(image.empty());
  EXPECT_TRUE(image == test::read_bytes(dir / "new.png"));
  // The values did reach the renderer: the defaults (aces, all) draw something else.
  EXPECT_FALSE(image == test::read_bytes(dir / "default.png"));
  EXPECT_EQ(count_lines_with(old.err, "lightbake: note: --curve is deprecated, use --tone\n"), 1)
      << old.err;
  EXPECT_EQ(count_lines_with(old.err, "lightbake: note: --term is deprecated, use --terms\n"), 1)
      << old.err;
  EXPECT_EQ(std::count(old.err.begin(), old.err.end(), '\n'), 2) << old.err;
  EXPECT_EQ(count_lines_with(now.err, "deprecated"), 0) << now.err;
}

TEST(OptionNames, BothSpellingsAtOnceAreRefused) {
  const fs::path dir = test::fresh_dir("option_names", "both");
  const test::CliRun run = snapshot(dir, "--tone clamp --curve aces", "x.png");
  EXPECT_NE(run.status, 0);
  EXPECT_NE(run.err.find("--curve"), std::string::npos) << run.err;
  EXPECT_FALSE(fs::exists(dir / "x.png"));
}

TEST(OptionNames, HelpListsOnlyTheNewNames) {
  for (const std::string command : {"snapshot", "view"}) {
    const test::CliRun help = test::run_lightbake(command + " --help");
    ASSERT_EQ(help.status, 0) << help.err;
    EXPECT_NE(help.out.find("--terms"), std::string::npos) << help.out;
    EXPECT_EQ(help.out.find("--term "), std::string::npos) << help.out;
    EXPECT_EQ(help.out.find("--curve"), std::string::npos) << help.out;
    EXPECT_NE(help.out.find("--threads"), std::string::npos) << help.out;
  }
  for (const std::string command : {"bake", "render", "reference", "export"}) {
    const test::CliRun help = test::run_lightbake(command + " --help");
    EXPECT_NE(help.out.find("--threads"), std::string::npos) << command << "\n" << help.out;
  }
}

}  // namespace
}  // namespace lb
