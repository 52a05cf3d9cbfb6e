// `lightbake compare` end to end: files in, one JSON line out, one-line errors naming the file.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "bake/io/image_io.h"
#include "test_helpers.h"

namespace lb {
namespace {

namespace fs = std::filesystem;

fs::path fresh_dir(const std::string& name) {
  return test::fresh_dir("compare_cli", name);
}

std::string read_text(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

// Runs `lightbake compare ARGS`; returns the exit status, stdout and stderr in out/err.
int run_compare(const std::string& args, const fs::path& dir, std::string& out, std::string& err) {
  const std::string binary = std::string(LIGHTBAKE_BINARY_DIR) + "/app/lightbake";
  const std::string command = "'" + binary + "' compare " + args + " > '" +
                              (dir / "out.txt").string() + "' 2> '" + (dir / "err.txt").string() +
                              "'";
  const int status = std::system(command.c_str());
  out = read_text(dir / "out.txt");
  err = read_text(dir / "err.txt");
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string write_constant(const fs::path& dir, const std::string& name, int width, int height,
                           float value) {
  const std::string path = (dir / name).string();
  write_exr(path, Image(width, height, 3, value), ExrPixelType::float32);
  return path;
}

TEST(CompareCli, PrintsOneJsonLineWithTheClosedFormMetrics) {
  const fs::path dir = fresh_dir("json");
  const std::string a = write_constant(dir, "a.exr", 32, 16, 1.1f);
  const std::string b = write_constant(dir, "b.exr", 32, 16, 1.0f);
  const std::string error_png = (dir / "error.png").string();
  std::string out, err;
  ASSERT_EQ(
      run_compare("'" + a + "' '" + b + "' --region 0,0,16,16 --error-image '" + error_png + "'",
                  dir, out, err),
      0)
      << err;
  EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;
  const auto json = nlohmann::json::parse(out);
  const double offset = double(1.1f) - 1.0;
  EXPECT_NEAR(json["mre"].get<double>(), offset / 1.01, 1e-12);
  EXPECT_NEAR(json["sum_ratio_total"].get<double>(), 1.0 + offset, 1e-12);
  EXPECT_NEAR(json["rmse"].get<double>(), offset, 1e-12);
  EXPECT_EQ(json["pixels"].get<int>(), 256);
  const Image error = read_image(error_png);
  EXPECT_EQ(error.width, 32);
  EXPECT_EQ(error.height, 16);
}

TEST(CompareCli, SubtractComparesAgainstTheReferenceMinusATerm) {
  const fs::path dir = fresh_dir("subtract");
  const std::string a = write_constant(dir, "a.exr", 8, 8, 0.5f);
  const std::string b = write_constant(dir, "b.exr", 8, 8, 2.0f);
  const std::string c = write_constant(dir, "c.exr", 8, 8, 1.5f);
  std::string out, err;
  ASSERT_EQ(run_compare("'" + a + "' '" + b + "' --subtract '" + c + "'", dir, out, err), 0) << err;
  EXPECT_NEAR(nlohmann::json::parse(out)["sum_ratio_total"].get<double>(), 1.0, 1e-12);
}

TEST(CompareCli, SizeMismatchIsOneLineNamingTheFile) {
  const fs::path dir = fresh_dir("mismatch");
  const std::string a = write_constant(dir, "a.exr", 32, 16, 1.0f);
  const std::string b = write_constant(dir, "b.exr", 32, 15, 1.0f);
  std::string out, err;
  EXPECT_EQ(run_compare("'" + a + "' '" + b + "'", dir, out, err), 1);
  EXPECT_EQ(err, "lightbake: error: " + b + ": size 32x15 differs from " + a + " (32x16)\n");
  EXPECT_TRUE(out.empty()) << out;
}

}  // namespace
}  // namespace lb
