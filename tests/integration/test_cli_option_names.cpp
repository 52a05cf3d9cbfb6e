// One name per concept across subcommands (docs/command-line.md, "One name per concept"); old
// spellings are unknown options.

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "test_helpers.h"

namespace lb {
namespace {

namespace fs = std::filesystem;

// `snapshot ... OPTIONS -o NAME` of the Cornell box, direct light only, 80 x 60.
test::CliRun snapshot(const fs::path& dir, const std::string& options, const std::string& name) {
  std::string args = "snapshot '";
  args += test::source_dir();
  args += "/scenes/cornell_box.toml' --no-bake --size 80x60 -q " + options + " -o " + name;
  return test::run_lightbake(args, dir.string());
}

TEST(OptionNames, ToneAndTermsReachTheRenderer) {
  const fs::path dir = test::fresh_dir("option_names", "snapshot");
  const test::CliRun now = snapshot(dir, "--tone clamp --terms radiosity", "new.png");
  const test::CliRun plain = snapshot(dir, "", "default.png");
  ASSERT_EQ(now.status, 0) << now.err;
  ASSERT_EQ(plain.status, 0) << plain.err;
  const std::string image = test::read_bytes(dir / "new.png");
  EXPECT_FALSE(image.empty());
  // The defaults (aces, all) draw something else.
  EXPECT_FALSE(image == test::read_bytes(dir / "default.png"));
}

// No aliases before 1.0: an old spelling is an unknown option, refused by CLI11 before any work.
TEST(OptionNames, OldSpellingsAreUnknownOptions) {
  const fs::path dir = test::fresh_dir("option_names", "old");
  const std::string box = "'" + std::string(test::source_dir()) + "/scenes/cornell_box.toml'";
  const std::pair<std::string, std::string> old_names[] = {
      {"snapshot", "--curve clamp"},      {"snapshot", "--term radiosity"},
      {"view", "--term radiosity"},       {"bake", "--max-depth 9"},
      {"bake", "--emitters-lights-only"},
  };
  for (const auto& [command, option] : old_names) {
    const test::CliRun run =
        test::run_lightbake(command + " " + box + " " + option + " -o x.out", dir.string());
    EXPECT_NE(run.status, 0) << command << " " << option;
    const std::string name = option.substr(0, option.find(' '));
    const std::string first_line = run.err.substr(0, run.err.find('\n'));
    EXPECT_NE(first_line.find("not expected"), std::string::npos) << run.err;
    EXPECT_NE(first_line.find(name), std::string::npos) << run.err;
    EXPECT_FALSE(fs::exists(dir / "x.out")) << command << " " << option;
  }
}

// The options render, reference, snapshot and view share are one table (app/view_options.h),
// which checks them in every command that takes them: one line naming the option, status 1,
// before any work.
TEST(OptionNames, SharedOptionsAreCheckedByTheTableInEveryCommand) {
  const fs::path dir = test::fresh_dir("option_names", "table");
  const std::string box = "'" + std::string(test::source_dir()) + "/scenes/cornell_box.toml'";
  const struct {
    const char* option;
    std::vector<std::string> commands;
    const char* message;
  } cases[] = {
      {"--size 0x1", {"render", "reference", "snapshot", "view"},
       "--size '0x1': each side must be in [1, 16384]"},
      {"--size wide", {"render", "reference", "snapshot", "view"},
       "--size 'wide': expected WIDTHxHEIGHT, e.g. 1024x768"},
      {"--tone sepia", {"render", "reference", "snapshot"},
       "--tone: expected clamp, reinhard or aces, got 'sepia'"},
      {"--spp 3", {"render", "view"}, "--spp: expected a square number of samples per pixel"},
      {"--terms all", {"render"}, "--terms: expected a list of direct, map and radiosity, got 'all'"},
      {"--terms direct,glow", {"render"}, "--terms: expected a list of direct, map and radiosity"},
      {"--terms map", {"reference"}, "--terms: expected all or direct, got 'map'"},
      {"--terms glow", {"snapshot", "view"}, "--terms: unknown term 'glow'"},
      {"--direct sometimes", {"snapshot", "view"},
       "--direct: expected full or stochastic, got 'sometimes'"},
      {"--passes 0", {"render"}, "--passes: must be at least 1"},
      {"--passes -1", {"view"}, "--passes: must be 0 (no end) or more"},
      {"--frames 0", {"snapshot"}, "--frames: must be 1 or more"},
  };
  for (const auto& c : cases)
    for (const std::string& command : c.commands) {
      const std::string output = command == "view" ? "" : " -o x.png";
      const test::CliRun run = test::run_lightbake(
          command + " " + box + " " + c.option + output, dir.string());
      EXPECT_EQ(run.status, 1) << command << " " << c.option << ": " << run.err;
      EXPECT_EQ(run.err.rfind(std::string("lightbake: error: ") + c.message, 0), 0u)
          << command << " " << c.option << ": " << run.err;
      EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
      EXPECT_FALSE(fs::exists(dir / "x.png")) << command << " " << c.option;
    }
}

TEST(OptionNames, HelpListsTermsAndThreads) {
  for (const std::string command : {"snapshot", "view"}) {
    const test::CliRun help = test::run_lightbake(command + " --help");
    ASSERT_EQ(help.status, 0) << help.err;
    EXPECT_NE(help.out.find("--terms"), std::string::npos) << help.out;
    EXPECT_NE(help.out.find("--threads"), std::string::npos) << help.out;
  }
  for (const std::string command : {"bake", "render", "reference", "export"}) {
    const test::CliRun help = test::run_lightbake(command + " --help");
    EXPECT_NE(help.out.find("--threads"), std::string::npos) << command << "\n" << help.out;
  }
}

}  // namespace
}  // namespace lb
