// Sharded reference renders: `reference --shard i/n` on n processes and `lightbake merge` give
// the bits of the whole render (image and report), and merge refuses what is not one render's
// complete set of shards (docs/farm.md).

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "bake/io/image_io.h"
#include "test_helpers.h"

namespace lb {
namespace {

namespace fs = std::filesystem;

class ReferenceShards : public testing::Test {
 protected:
  static void SetUpTestSuite() {
    // One folder per test process: ctest runs each test of the suite in its own process.
    dir_ = test::fresh_dir("reference_shards", "cornell_glass_" + std::to_string(getpid()));
  }
  // Glass (light tracing's caustic splats), 9 passes: odd, so the halves are unequal and the
  // 4 shards hold 3, 2, 2 and 2 passes.
  static test::CliRun reference(const std::string& extra,
                                const std::string& scene = "cornell_glass") {
    return test::run_lightbake("reference -q '" + test::source_dir() + "/scenes/" + scene +
                                   ".toml' --size 40x30 --spp 9 " + extra,
                               dir_);
  }
  static std::vector<float> pixels(const std::string& name) {
    return read_image((fs::path(dir_) / name).string()).pixels;
  }
  static nlohmann::json report(const std::string& name) {
    std::ifstream in(fs::path(dir_) / name);
    return nlohmann::json::parse(in);
  }
  static inline std::string dir_;
};

TEST_F(ReferenceShards, FourShardsMergeToTheBitsOfTheWholeRender) {
  ASSERT_EQ(reference("-o whole.exr").status, 0);
  for (int i = 0; i < 4; ++i) {
    // Thread counts differ per shard, as on unequal machines.
    const test::CliRun run =
        reference("-o part" + std::to_string(i) + ".refshard --shard " + std::to_string(i) +
                  "/4 --threads " + std::to_string(1 + i % 2));
    ASSERT_EQ(run.status, 0) << run.err;
  }
  EXPECT_EQ(report("part0.json").at("passes"), 3);
  EXPECT_EQ(report("part3.json").at("passes"), 2);
  // Given in any order.
  const test::CliRun merged = test::run_lightbake(
      "merge part3.refshard part1.refshard part0.refshard part2.refshard -o merged.exr", dir_);
  ASSERT_EQ(merged.status, 0) << merged.err;
  const std::vector<float> whole = pixels("whole.exr");
  ASSERT_FALSE(whole.empty());
  EXPECT_TRUE(test::same_bits(pixels("merged.exr"), whole));
  // The report's estimates over all passes too: the noise from the even/odd halves and the
  // per-pass means, the image mean and the rays.
  const nlohmann::json a = report("whole.json"), b = report("merged.json");
  for (const char* key : {"noise", "image_mean_radiance", "rays", "passes", "lost_samples",
                          "samples_per_pixel", "seed", "width", "height", "terms", "camera"})
    EXPECT_EQ(a.at(key), b.at(key)) << key;
  EXPECT_GT(a.at("noise").at("pixel_relative_standard_error").get<double>(), 0.0);
  ASSERT_EQ(
      test::run_lightbake(
          "merge part0.refshard part1.refshard part2.refshard part3.refshard -o merged.png", dir_)
          .status,
      0);
  EXPECT_TRUE(fs::exists(fs::path(dir_) / "merged.png"));
}

// `--window x0,y0,x1,y1`: the window's pixels have the bits of the same pixels of the whole
// render (eye paths on their whole-image streams, every light path traced), 0 elsewhere; so
// do a windowed render's shards, merged.
TEST_F(ReferenceShards, AWindowHasTheBitsOfTheWholeRenderAlsoInShards) {
  ASSERT_EQ(reference("-o whole_w.exr").status, 0);
  // The lower left, where the ball and its floor caustic are (light tracing's splats).
  const int x0 = 4, y0 = 14, x1 = 24, y1 = 30, width = 40;
  const std::string window = " --window " + std::to_string(x0) + "," + std::to_string(y0) + "," +
                             std::to_string(x1) + "," + std::to_string(y1);
  ASSERT_EQ(reference("-o window.exr --threads 1" + window).status, 0);
  for (int i = 0; i < 2; ++i)
    ASSERT_EQ(reference("-o wpart" + std::to_string(i) + ".refshard --shard " + std::to_string(i) +
                        "/2" + window)
                  .status,
              0);
  const test::CliRun merged =
      test::run_lightbake("merge wpart1.refshard wpart0.refshard -o wmerged.exr", dir_);
  ASSERT_EQ(merged.status, 0) << merged.err;
  const std::vector<float> whole = pixels("whole_w.exr"), part = pixels("window.exr");
  ASSERT_EQ(part.size(), whole.size());  // the whole image's size
  EXPECT_TRUE(test::same_bits(pixels("wmerged.exr"), part));
  size_t differing = 0, inside = 0, lit_inside = 0, nonzero_outside = 0;
  for (size_t i = 0; i < whole.size(); ++i) {
    const int x = int(i / 3) % width, y = int(i / 3) / width;
    if (x >= x0 && x < x1 && y >= y0 && y < y1) {
      ++inside;
      lit_inside += whole[i] > 0.0f;
      differing += std::memcmp(&whole[i], &part[i], sizeof(float)) != 0;
    } else {
      nonzero_outside += part[i] != 0.0f;
    }
  }
  EXPECT_EQ(inside, size_t((x1 - x0) * (y1 - y0) * 3));
  EXPECT_GT(lit_inside, inside / 2);
  EXPECT_EQ(differing, 0u);
  EXPECT_EQ(nonzero_outside, 0u);
  const nlohmann::json w = report("window.json"), a = report("whole_w.json");
  EXPECT_EQ(w.at("rays").at("camera"), (x1 - x0) * (y1 - y0) * 9);
  EXPECT_EQ(w.at("rays").at("light_paths"), a.at("rays").at("light_paths"));  // all traced
  // Caustic splats were connected inside the window, fewer than in the whole image.
  EXPECT_GT(w.at("rays").at("connection").get<uint64_t>(), 0u);
  EXPECT_LT(w.at("rays").at("connection").get<uint64_t>(),
            a.at("rays").at("connection").get<uint64_t>());
  EXPECT_EQ(w.at("window"), nlohmann::json({{"x0", x0}, {"y0", y0}, {"x1", x1}, {"y1", y1}}));
  // Bad windows, refused in one line naming the option, nothing written.
  for (const char* bad : {"0,0,0,10", "10,5,4,8", "30,20,41,30", "-1,0,5,5", "1,2,3"}) {
    const test::CliRun run = reference("-o bad_w.exr --window " + std::string(bad));
    EXPECT_NE(run.status, 0) << bad;
    EXPECT_EQ(run.err.rfind("lightbake: error: --window '" + std::string(bad) + "'", 0), 0u)
        << run.err;
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
  }
  EXPECT_FALSE(fs::exists(fs::path(dir_) / "bad_w.exr"));
}

TEST_F(ReferenceShards, MergeRefusesIncompleteRepeatedForeignOrAlteredShards) {
  for (int i = 0; i < 2; ++i)
    ASSERT_EQ(
        reference("-o half" + std::to_string(i) + ".refshard --shard " + std::to_string(i) + "/2")
            .status,
        0);
  ASSERT_EQ(reference("-o other_seed.refshard --shard 1/2 --seed 7").status, 0);
  ASSERT_EQ(reference("-o other_count.refshard --shard 1/3").status, 0);
  ASSERT_EQ(reference("-o other_scene.refshard --shard 1/2", "cornell_box").status, 0);
  fs::copy_file(fs::path(dir_) / "half1.refshard", fs::path(dir_) / "altered.refshard");
  fs::copy_file(fs::path(dir_) / "half1.json", fs::path(dir_) / "altered.json");
  {
    std::fstream f(fs::path(dir_) / "altered.refshard",
                   std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(200);
    f.put('\x7f');
  }
  const auto error_of = [](const std::string& args) {
    const test::CliRun run = test::run_lightbake("merge " + args + " -o bad.exr", dir_);
    EXPECT_NE(run.status, 0) << args;
    EXPECT_FALSE(fs::exists(fs::path(dir_) / "bad.exr")) << args;  // nothing written
    EXPECT_FALSE(fs::exists(fs::path(dir_) / "bad.json")) << args;
    return run.err;
  };
  const auto expect_error = [&](const std::string& args, const std::string& message) {
    const std::string err = error_of(args);
    EXPECT_NE(err.find(message), std::string::npos) << args << ": " << err;
  };
  expect_error("half0.refshard", "shard 1 of 2 is missing");
  expect_error("half0.refshard half0.refshard", "half0.refshard: shard 0 given twice");
  expect_error("half0.refshard other_seed.refshard",
               "other_seed.refshard: seed 7 differs from half0.refshard's 1: not a shard of the "
               "same render");
  expect_error("half0.refshard other_count.refshard",
               "other_count.refshard: shard_count 3 differs from half0.refshard's 2");
  expect_error("half0.refshard other_scene.refshard", "other_scene.refshard: scene_hash");
  expect_error("half0.refshard altered.refshard",
               "altered.refshard: its size or FNV-1a differs from");
  expect_error("half0.refshard whole.exr", "give shards of one kind, not both (.refshard");
  // A shard is a .refshard, has no time limit, and its index is inside its count; each refused
  // before any work.
  EXPECT_NE(reference("-o s.exr --shard 0/2").err.find("a reference shard is written as .refshard"),
            std::string::npos);
  EXPECT_NE(reference("-o s.refshard --shard 0/2 --time-limit 5")
                .err.find("--time-limit: not with "
                          "--shard"),
            std::string::npos);
  EXPECT_NE(
      reference("-o s.refshard --shard 2/2").err.find("--shard 2/2: needs 0 <= INDEX < COUNT"),
      std::string::npos);
  EXPECT_FALSE(fs::exists(fs::path(dir_) / "s.refshard"));
  // A file lightbake did not write is not replaced.
  std::ofstream(fs::path(dir_) / "mine.refshard") << "my notes";
  EXPECT_NE(reference("-o mine.refshard --shard 0/2").err.find("was not written by lightbake"),
            std::string::npos);
}

}  // namespace
}  // namespace lb
