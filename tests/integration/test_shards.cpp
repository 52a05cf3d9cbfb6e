// Sharded HQ renders: `render --shard i/n` on n processes and `lightbake merge` give the bits of
// the whole render, and merge refuses what is not one render's complete set of shards.

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "bake/io/image_io.h"
#include "test_helpers.h"

namespace lb {
namespace {

namespace fs = std::filesystem;

class Shards : public testing::Test {
 protected:
  static void SetUpTestSuite() {
    // One folder per test process: ctest runs each test of the suite in its own process, at
    // the same time, and each sets the suite up.
    dir_ = test::fresh_dir("shards", "cornell_glass_" + std::to_string(getpid()));
    scene_ = "'" + test::source_dir();
    scene_.append("/scenes/cornell_glass.toml' bake");
    ASSERT_EQ(
        test::run_lightbake("bake -q " + scene_.substr(0, scene_.size() - 5) + " -o bake", dir_)
            .status,
        0);
  }
  static test::CliRun render(const std::string& extra) {
    // Glass (specular paths, light-choice reuse) and a size that is not a multiple of the tiles.
    return test::run_lightbake("render -q " + scene_ + " --size 90x70 --spp 4 " + extra, dir_);
  }
  static std::vector<float> pixels(const std::string& name) {
    return read_image((fs::path(dir_) / name).string()).pixels;
  }
  static std::string path(const std::string& name) { return (fs::path(dir_) / name).string(); }
  static inline std::string dir_, scene_;
};

TEST_F(Shards, FourShardsMergeToTheBitsOfTheWholeRender) {
  ASSERT_EQ(render("-o whole.exr").status, 0);
  std::string list;
  for (int i = 0; i < 4; ++i) {
    const std::string name = "part" + std::to_string(i) + ".rendershard";
    // Thread counts differ per shard, as on unequal machines.
    const test::CliRun run = render("-o " + name + " --shard " + std::to_string(i) +
                                    "/4 --threads " + std::to_string(1 + i % 2));
    ASSERT_EQ(run.status, 0) << run.err;
    list += " " + name;
  }
  // Each shard holds only its tiles: a quarter of the pixels (12-byte RGB), give or take a tile.
  const size_t part = fs::file_size(path("part1.rendershard")) / 12, all = 90 * 70;
  EXPECT_GT(part, all / 6);
  EXPECT_LT(part, all / 3);
  // Given in any order.
  const test::CliRun merged = test::run_lightbake(
      "merge part3.rendershard part1.rendershard part0.rendershard part2.rendershard -o "
      "merged.exr",
      dir_);
  ASSERT_EQ(merged.status, 0) << merged.err;
  const std::vector<float> whole = pixels("whole.exr");
  ASSERT_FALSE(whole.empty());
  EXPECT_TRUE(test::same_bits(pixels("merged.exr"), whole));
  ASSERT_EQ(test::run_lightbake("merge" + list + " -o merged.png", dir_).status, 0);
  EXPECT_TRUE(fs::exists(fs::path(dir_) / "merged.png"));
}

TEST_F(Shards, MergeRefusesIncompleteRepeatedOrForeignShards) {
  for (int i = 0; i < 2; ++i)
    ASSERT_EQ(render("-o half" + std::to_string(i) + ".rendershard --shard " + std::to_string(i) +
                     "/2")
                  .status,
              0);
  ASSERT_EQ(render("-o other_seed.rendershard --shard 1/2 --seed 7").status, 0);
  const auto error_of = [](const std::string& args) {
    const test::CliRun run = test::run_lightbake("merge " + args, dir_);
    EXPECT_NE(run.status, 0) << args;
    EXPECT_FALSE(fs::exists(fs::path(dir_) / "bad.exr")) << args;  // nothing half written
    return run.err;
  };
  EXPECT_NE(error_of("half0.rendershard -o bad.exr").find("shard 1 of 2 is missing"),
            std::string::npos);
  EXPECT_NE(error_of("half0.rendershard half0.rendershard -o bad.exr")
                .find("half0.rendershard: shard 0 given twice"),
            std::string::npos);
  EXPECT_NE(error_of("half0.rendershard other_seed.rendershard -o bad.exr")
                .find("other_seed.rendershard: seed 7 differs from half0.rendershard's 1: not a "
                      "shard of the same render"),
            std::string::npos);
  // Another file named as a shard: it has no report.
  fs::copy_file(path("bake/illumination.exr"), path("foreign.rendershard"));
  EXPECT_NE(error_of("half0.rendershard foreign.rendershard -o bad.exr")
                .find("cannot read the shard's report"),
            std::string::npos);
  // A shard whose data lost a bit: its FNV-1a is not its report's.
  fs::copy_file(path("half1.rendershard"), path("flipped.rendershard"));
  fs::copy_file(path("half1.json"), path("flipped.json"));
  {
    std::fstream file(path("flipped.rendershard"), std::ios::in | std::ios::out | std::ios::binary);
    file.seekg(-5, std::ios::end);
    const char byte = char(file.get() ^ 1);
    file.seekp(-5, std::ios::end);
    file.put(byte);
  }
  EXPECT_NE(error_of("half0.rendershard flipped.rendershard -o bad.exr")
                .find("flipped.rendershard: its size or FNV-1a differs from"),
            std::string::npos);
  // A shard is a .rendershard, and a shard index outside its count is refused before any work.
  for (const char* name : {"s.exr", "s.png"})
    EXPECT_NE(render(std::string("-o ") + name + " --shard 0/2")
                  .err.find(std::string(name) + ": a render shard is written as .rendershard"),
              std::string::npos)
        << name;
  EXPECT_NE(error_of("half0.exr -o bad.exr").find("half0.exr: not a shard"), std::string::npos);
  EXPECT_NE(
      render("-o s.rendershard --shard 2/2").err.find("--shard 2/2: needs 0 <= INDEX < COUNT"),
      std::string::npos);
}

}  // namespace
}  // namespace lb
