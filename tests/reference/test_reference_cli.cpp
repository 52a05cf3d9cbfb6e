// `lightbake reference`: writes an EXR and a JSON report; refuses bad arguments with one line
// and a non-zero status, writing nothing.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "bake/io/image_io.h"
#include "test_helpers.h"

namespace lb {
namespace {

namespace fs = std::filesystem;

// 'text' for the shell (appends: GCC 12 warns falsely on "'" + std::string under -O3).
std::string quoted(const std::string& text) {
  std::string q(1, '\'');
  q.append(text);
  q.push_back('\'');
  return q;
}

// Runs `lightbake ARGS`; returns the exit status and what it wrote to stderr in `err_text`.
int run_cli(const std::string& args, std::string& err_text) {
  const test::CliRun run = test::run_lightbake(args);
  err_text = run.err;
  return run.status;
}

fs::path fresh_dir(const std::string& name) {
  return test::fresh_dir("reference_cli", name);
}

TEST(ReferenceCli, WritesAnExrAndAReport) {
  const fs::path dir = fresh_dir("reference_cli");
  const std::string scene = test::source_dir() + "/scenes/room.toml";
  const fs::path exr = dir / "room.exr", report = dir / "r.json";
  std::string err;
  ASSERT_EQ(run_cli("reference " + quoted(scene) + " --spp 4 --size 32x24 -q --seed 3 -o " +
                        quoted(exr.string()) + " --report " + quoted(report.string()),
                    err),
            0)
      << err;
  const Image image = read_image(exr.string());
  EXPECT_EQ(image.width, 32);
  EXPECT_EQ(image.height, 24);
  double sum = 0.0;
  for (float v : image.pixels) sum += double(v);
  EXPECT_GT(sum, 0.0);  // the room is lit

  std::ifstream in(report);
  const nlohmann::json json = nlohmann::json::parse(in);
  EXPECT_EQ(json["samples_per_pixel"], 4);
  EXPECT_EQ(json["passes"], 4);
  EXPECT_EQ(json["rays"]["camera"], 32 * 24 * 4);
  EXPECT_GT(json["rays"]["shadow"].get<double>(), 0.0);
  EXPECT_GT(json["rays"]["light"].get<double>(), 0.0);
  EXPECT_GE(json["cpu_seconds"].get<double>(), 0.0);
  EXPECT_GT(json["wall_seconds"].get<double>(), 0.0);
  EXPECT_GT(json["noise"]["pixel_relative_standard_error"].get<double>(), 0.0);
}

// Ctrl-C: tests/integration/test_cli_cancel.cpp (after the first progress line, as for
// every command).

TEST(ReferenceCli, RefusesBadArgumentsAndWritesNothing) {
  const fs::path dir = fresh_dir("reference_cli_bad");
  const std::string scene = quoted(test::source_dir() + "/scenes/room.toml");
  const std::string out = " -o " + quoted((dir / "x.exr").string());
  const struct {
    std::string args, message;
  } cases[] = {
      {"--spp 0", "spp must be at least 1"},
      {"--size 0x10", "--size"},
      {"--terms indirect", "--terms: expected all or direct"},
      {"--time-limit -1", "time limit"},
      {"--camera nowhere", "--camera"},
  };
  for (const auto& c : cases) {
    std::string err;
    EXPECT_NE(run_cli("reference " + scene + " -q " + c.args + out, err), 0) << c.args;
    EXPECT_NE(err.find(c.message), std::string::npos) << c.args << ": " << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;  // one line
  }
  std::string err;
  EXPECT_NE(run_cli("reference " + scene + " -q -o " + quoted((dir / "x.jpg").string()), err), 0);
  EXPECT_NE(err.find("must be .exr or .png"), std::string::npos) << err;
  EXPECT_NE(run_cli("reference " + quoted((dir / "missing.toml").string()) + " -q" + out, err), 0);
  EXPECT_FALSE(fs::exists(dir / "x.exr"));
  EXPECT_FALSE(fs::exists(dir / "x.json"));
}

}  // namespace
}  // namespace lb
