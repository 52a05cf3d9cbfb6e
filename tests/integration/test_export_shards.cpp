// Sharded exports: the direct light of `export --contents all --shard i/n` on n processes and
// `lightbake merge` give the glTF of the whole export byte for byte (the EXR beside it carries
// its write time, so its texel values are compared), and merge refuses what is not one
// export's complete set of shards (docs/farm.md).

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "bake/io/image_io.h"
#include "bake/binary_file.h"
#include "test_helpers.h"

namespace lb {
namespace {

namespace fs = std::filesystem;

class ExportShards : public testing::Test {
 protected:
  static void SetUpTestSuite() {
    // One folder per test process: ctest runs each test of the suite in its own process.
    dir_ = test::fresh_dir("export_shards", "cornell_glass_" + std::to_string(getpid()));
    scene_ = "'" + test::source_dir();
    scene_.append("/scenes/cornell_glass.toml'");
    ASSERT_EQ(test::run_lightbake("bake -q " + scene_ + " --quality draft -o bake", dir_).status,
              0);
  }
  // Glass and an atlas of 106 x 469 texels (the floor's charts split along the blocks'
  // footprints, bake/contact_conform.h): 15 bands of 32 rows, which 4 shards would hold unevenly
  // in whole bands, so each takes one range of rows of about a quarter of the work.
  static test::CliRun export_(const std::string& extra, const std::string& bake = "bake") {
    return test::run_lightbake("export -q " + scene_ + " " + bake + " --contents all " + extra,
                               dir_);
  }
  static std::string path(const std::string& name) { return (fs::path(dir_) / name).string(); }
  static inline std::string dir_, scene_;
};

TEST_F(ExportShards, FourShardsMergeToTheBytesOfTheWholeExport) {
  ASSERT_EQ(export_("-o whole.glb").status, 0);
  for (int i = 0; i < 4; ++i) {
    // Thread counts differ per shard, as on unequal machines.
    const test::CliRun run =
        export_("-o part" + std::to_string(i) + ".texshard --shard " + std::to_string(i) +
                "/4 --threads " + std::to_string(1 + i % 2));
    ASSERT_EQ(run.status, 0) << run.err;
  }
  fs::create_directories(path("merged"));
  // Given in any order; the same file name, which the glTF records for its EXR.
  const test::CliRun merged = test::run_lightbake(
      "merge -q part3.texshard part1.texshard part0.texshard part2.texshard -o merged/whole.glb",
      dir_);
  ASSERT_EQ(merged.status, 0) << merged.err;
  const std::string whole = test::read_bytes(path("whole.glb"));
  ASSERT_GT(whole.size(), 1000u);
  EXPECT_TRUE(whole == test::read_bytes(path("merged/whole.glb")));
  const Image a = read_image(path("whole.lightmap.exr")),
              b = read_image(path("merged/whole.lightmap.exr"));
  EXPECT_EQ(a.width, 106);
  EXPECT_TRUE(test::same_bits(a.pixels, b.pixels));
  // Each shard holds only its rows, the one after the other's: a 32-byte header (the container's
  // 24, first and end row) and its rows of 106 texels x 24 bytes (the direct term and its ratio
  // estimator's denominator, which the merge then need not sample). Their surface points (the work
  // the rows are split by) are within 4% of a quarter of all (a row holds at most 106 x 16, under
  // 1% of a quarter). Their shadow rays are not: points facing no light trace none.
  int next_row = 0;
  uint64_t points[4] = {}, all_points = 0;
  for (int i = 0; i < 4; ++i) {
    std::ifstream in(path("part" + std::to_string(i) + ".json"));
    const nlohmann::json report = nlohmann::json::parse(in);
    const int begin = report.at("rows").at("begin"), end = report.at("rows").at("end");
    EXPECT_EQ(begin, next_row) << "shard " << i;
    next_row = end;
    EXPECT_EQ(test::read_bytes(path("part" + std::to_string(i) + ".texshard")).size(),
              32u + size_t(end - begin) * 106u * 24u);
    points[i] = report.at("points").get<uint64_t>();
    all_points += points[i];
  }
  EXPECT_EQ(next_row, 469);
  for (int i = 0; i < 4; ++i)
    EXPECT_NEAR(double(points[i]) / double(all_points), 0.25, 0.25 * 0.04) << "shard " << i;
}

// `--denoise` on shards: each records it, and the merge runs Open Image Denoise on the joined
// direct term, as the whole export does (its library from build/pypi, which scripts/test.sh
// fills: without it this test fails, never skips).
TEST_F(ExportShards, DenoisedShardsMergeToTheBytesOfTheWholeDenoisedExport) {
  ASSERT_EQ(export_("--direct-samples 2 --denoise -o denoised.glb").status, 0);
  ASSERT_EQ(export_("--direct-samples 2 -o plain.glb").status, 0);
  for (int i = 0; i < 2; ++i) {
    const test::CliRun run = export_("--direct-samples 2 --denoise -o denoised" +
                                     std::to_string(i) + ".texshard --shard " +
                                     std::to_string(i) + "/2");
    ASSERT_EQ(run.status, 0) << run.err;
  }
  fs::create_directories(path("denoised_merge"));
  const test::CliRun merged = test::run_lightbake(
      "merge -q denoised1.texshard denoised0.texshard -o denoised_merge/denoised.glb", dir_);
  ASSERT_EQ(merged.status, 0) << merged.err;
  EXPECT_TRUE(test::read_bytes(path("denoised.glb")) ==
              test::read_bytes(path("denoised_merge/denoised.glb")));
  const Image whole = read_image(path("denoised.lightmap.exr")),
              joined = read_image(path("denoised_merge/denoised.lightmap.exr")),
              plain = read_image(path("plain.lightmap.exr"));
  EXPECT_TRUE(test::same_bits(whole.pixels, joined.pixels));
  EXPECT_FALSE(test::same_bits(whole.pixels, plain.pixels));  // the denoiser did run
  // A shard without --denoise is not of the same set.
  ASSERT_EQ(export_("--direct-samples 2 -o plain1.texshard --shard 1/2").status, 0);
  const test::CliRun mixed =
      test::run_lightbake("merge -q denoised0.texshard plain1.texshard -o mixed.glb", dir_);
  EXPECT_NE(mixed.status, 0);
  EXPECT_FALSE(fs::exists(path("mixed.glb")));
}

// `--shadow-rays` on shards: every shard runs the pilot over the whole map, so its rows get the
// unsharded plan of the cells' rays, and carries its rows' ratio denominator to the merge.
TEST_F(ExportShards, AdaptiveShadowRaysMergeToTheBytesOfTheWholeExport) {
  const std::string rays = "--direct-samples 4 --shadow-rays 2";
  ASSERT_EQ(export_(rays + " -o quarter.glb").status, 0);
  ASSERT_EQ(export_("--direct-samples 4 -o every_ray.glb").status, 0);
  for (int i = 0; i < 3; ++i) {
    const test::CliRun run = export_(rays + " -o quarter" + std::to_string(i) +
                                     ".texshard --shard " + std::to_string(i) + "/3 --threads " +
                                     std::to_string(1 + i % 2));
    ASSERT_EQ(run.status, 0) << run.err;
  }
  fs::create_directories(path("quarter_merge"));
  const test::CliRun merged = test::run_lightbake(
      "merge -q quarter2.texshard quarter0.texshard quarter1.texshard "
      "-o quarter_merge/quarter.glb",
      dir_);
  ASSERT_EQ(merged.status, 0) << merged.err;
  EXPECT_TRUE(test::read_bytes(path("quarter.glb")) ==
              test::read_bytes(path("quarter_merge/quarter.glb")));
  const Image whole = read_image(path("quarter.lightmap.exr")),
              joined = read_image(path("quarter_merge/quarter.lightmap.exr")),
              every_ray = read_image(path("every_ray.lightmap.exr"));
  EXPECT_TRUE(test::same_bits(whole.pixels, joined.pixels));
  EXPECT_FALSE(test::same_bits(whole.pixels, every_ray.pixels));  // fewer rays were cast
}

// `--directional`: each shard bakes its rows' direct term with its L1 (the same points and
// shadow rays as the whole export's), the merge makes the soft and caustic terms' bands from
// the bake as the whole export does: the same glTF, byte for byte, in either encoding
// (`--directional-share` given to the shards or to the merge).
TEST_F(ExportShards, DirectionalShardsMergeToTheBytesOfTheWholeDirectionalExport) {
  const std::string options = "--direct-samples 2 --directional";
  ASSERT_EQ(export_(options + " -o directional.glb").status, 0);
  ASSERT_EQ(export_(options + " --directional-share -o share.glb").status, 0);
  for (int i = 0; i < 3; ++i) {
    const test::CliRun run =
        export_(options + " -o band" + std::to_string(i) + ".texshard --shard " +
                std::to_string(i) + "/3 --threads " + std::to_string(1 + i % 2));
    ASSERT_EQ(run.status, 0) << run.err;
  }
  ASSERT_EQ(export_(options + " --directional-share -o band_share1.texshard --shard 1/3").status,
            0);
  fs::create_directories(path("directional_merge"));
  const test::CliRun merged = test::run_lightbake(
      "merge -q band2.texshard band0.texshard band1.texshard -o directional_merge/directional.glb",
      dir_);
  ASSERT_EQ(merged.status, 0) << merged.err;
  const std::string whole = test::read_bytes(path("directional.glb"));
  ASSERT_GT(whole.size(), 1000u);
  EXPECT_TRUE(whole == test::read_bytes(path("directional_merge/directional.glb")));
  EXPECT_TRUE(test::same_bits(read_image(path("directional.lightmap.exr")).pixels,
                              read_image(path("directional_merge/directional.lightmap.exr"))
                                  .pixels));
  fs::create_directories(path("share_merge"));
  const test::CliRun share = test::run_lightbake(
      "merge -q band0.texshard band1.texshard band2.texshard --directional-share "
      "-o share_merge/share.glb",
      dir_);
  ASSERT_EQ(share.status, 0) << share.err;
  const std::string whole_share = test::read_bytes(path("share.glb"));
  EXPECT_TRUE(whole_share == test::read_bytes(path("share_merge/share.glb")));
  EXPECT_GT(whole_share.size(), whole.size());  // the x map's alpha
  // Each shard: the 32-byte header and its rows of 106 nodes x (12 bytes of the direct term, 12
  // of its ratio denominator, 36 of its L1, 1 flag).
  for (int i = 0; i < 3; ++i) {
    std::ifstream in(path("band" + std::to_string(i) + ".json"));
    const nlohmann::json report = nlohmann::json::parse(in);
    const int rows =
        report.at("rows").at("end").get<int>() - report.at("rows").at("begin").get<int>();
    EXPECT_EQ(test::read_bytes(path("band" + std::to_string(i) + ".texshard")).size(),
              32u + size_t(rows) * 106u * 61u);
  }
  // Not one export's set: a shard recording the share with two that do not, a plain shard with
  // directional ones, the share asked of plain shards.
  const test::CliRun mixed_share = test::run_lightbake(
      "merge -q band0.texshard band_share1.texshard band2.texshard -o mixed_share.glb", dir_);
  EXPECT_NE(mixed_share.status, 0);
  ASSERT_EQ(export_("--direct-samples 2 -o plain1.texshard --shard 1/3").status, 0);
  const test::CliRun mixed = test::run_lightbake(
      "merge -q band0.texshard plain1.texshard band2.texshard -o mixed.glb", dir_);
  EXPECT_NE(mixed.status, 0);
  EXPECT_FALSE(fs::exists(path("mixed.glb")));
  EXPECT_FALSE(fs::exists(path("mixed_share.glb")));
  ASSERT_EQ(export_("--direct-samples 2 -o plain_all.texshard --shard 0/1").status, 0);
  const test::CliRun plain_share = test::run_lightbake(
      "merge -q plain_all.texshard --directional-share -o plain_share.glb", dir_);
  EXPECT_NE(plain_share.status, 0);
  EXPECT_NE(plain_share.err.find("--directional-share"), std::string::npos) << plain_share.err;
  EXPECT_FALSE(fs::exists(path("plain_share.glb")));
}

TEST_F(ExportShards, MergeRefusesIncompleteRepeatedForeignOrAlteredShards) {
  for (int i = 0; i < 2; ++i)
    ASSERT_EQ(
        export_("-o half" + std::to_string(i) + ".texshard --shard " + std::to_string(i) + "/2")
            .status,
        0);
  ASSERT_EQ(export_("-o other_samples.texshard --shard 1/2 --direct-samples 2").status, 0);
  ASSERT_EQ(export_("-o other_count.texshard --shard 1/3").status, 0);
  ASSERT_EQ(
      test::run_lightbake("bake -q " + scene_ + " --quality draft --seed 7 -o bake7", dir_).status,
      0);
  ASSERT_EQ(export_("-o other_bake.texshard --shard 1/2", "bake7").status, 0);
  fs::copy_file(path("half1.texshard"), path("altered.texshard"));
  fs::copy_file(path("half1.json"), path("altered.json"));
  // A shard of the format before (version 1: bands b mod n = i, no rows in its header).
  fs::copy_file(path("half1.texshard"), path("version1.texshard"));
  {
    std::ifstream in(path("half1.json"));
    nlohmann::json report = nlohmann::json::parse(in);
    report["version"] = 1;
    std::ofstream(path("version1.json")) << report.dump(2);
  }
  {
    std::fstream f(path("altered.texshard"), std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(100);
    f.put('\x7f');
  }
  // Shard 1 with its rows moved up one (bytes 24..31, after the container's header: first and end row), and a report
  // that vouches for the data, so only the partition check can refuse it.
  int half1_begin = 0;
  {
    std::string data = test::read_bytes(path("half1.texshard"));
    uint32_t rows[2];
    std::memcpy(rows, data.data() + 24, sizeof rows);
    half1_begin = int(rows[0]);
    rows[0] -= 1, rows[1] -= 1;
    std::memcpy(data.data() + 24, rows, sizeof rows);
    std::ofstream(path("shifted.texshard"), std::ios::binary) << data;
    std::ifstream in(path("half1.json"));
    nlohmann::json report = nlohmann::json::parse(in);
    Fnv1a hash;
    hash.add(data.data(), data.size());
    report["data"]["fnv1a"] = hex_digits(hash.value());
    std::ofstream(path("shifted.json")) << report.dump(2);
  }
  const auto expect_error = [](const std::string& args, const std::string& message) {
    const test::CliRun run = test::run_lightbake("merge -q " + args + " -o bad.glb", dir_);
    EXPECT_NE(run.status, 0) << args;
    EXPECT_NE(run.err.find(message), std::string::npos) << args << ": " << run.err;
    EXPECT_FALSE(fs::exists(path("bad.glb"))) << args;  // nothing written
    EXPECT_FALSE(fs::exists(path("bad.lightmap.exr"))) << args;
  };
  expect_error("half0.texshard", "shard 1 of 2 is missing");
  expect_error("half0.texshard half0.texshard", "half0.texshard: shard 0 given twice");
  expect_error("half0.texshard other_samples.texshard",
               "other_samples.texshard: direct_samples 2 differs from half0.texshard's 0: not a "
               "shard of the same export");
  expect_error("half0.texshard other_count.texshard",
               "other_count.texshard: shard_count 3 differs from half0.texshard's 2");
  expect_error("half0.texshard other_bake.texshard", "other_bake.texshard: bake_hash");
  expect_error("half0.texshard altered.texshard",
               "altered.texshard: its size or FNV-1a differs from");
  expect_error("half0.texshard half1.texshard --bake bake7", "bake7: bake hash");
  expect_error("half0.texshard shifted.texshard",
               "shifted.texshard: its rows begin at " + std::to_string(half1_begin - 1) +
                   ", not at " + std::to_string(half1_begin) +
                   " where shard 0's end: not a shard of the same partition");
  expect_error("half0.texshard version1.texshard",
               "version1.json: not the report of a `lightbake export --shard` run of this version "
               "(2)");
  // Refused before any work: other contents, no bake directory, another output kind.
  EXPECT_NE(test::run_lightbake("export -q " + scene_ + " bake -o s.texshard --shard 0/2", dir_)
                .err.find("only the direct light of --contents all is sharded"),
            std::string::npos);
  EXPECT_NE(
      test::run_lightbake("export -q " + scene_ + " --contents all -o s.texshard --shard 0/2", dir_)
          .err.find("give the bake directory"),
      std::string::npos);
  EXPECT_NE(export_("-o s.glb --shard 0/2").err.find("an export shard is written as .texshard"),
            std::string::npos);
  EXPECT_FALSE(fs::exists(path("s.texshard")));
  // A file lightbake did not write is not replaced.
  std::ofstream(path("mine.texshard")) << "my notes";
  EXPECT_NE(export_("-o mine.texshard --shard 0/2").err.find("was not written by lightbake"),
            std::string::npos);
}

}  // namespace
}  // namespace lb
