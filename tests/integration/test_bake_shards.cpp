// Sharded bakes (issue 16): `bake --shard i/n` on n processes and `lightbake merge` give the
// bake of one `lightbake bake`, pixel for pixel, and merge refuses what is not one bake's
// complete set of pass-1 shards.

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "bake/io/image_io.h"
#include "test_helpers.h"

namespace lb {
namespace {

namespace fs = std::filesystem;

class BakeShards : public testing::Test {
 protected:
  static void SetUpTestSuite() {
    // One folder per test process (ctest runs each test in its own process, at the same time).
    dir_ = test::fresh_dir("bake_shards", "cornell_glass_" + std::to_string(getpid()));
    scene_ = "'" + test::source_dir() + "/scenes/cornell_glass.toml'";
  }
  // Draft: 115k dense rays through the glass ball, 28 batches; about a second a bake.
  static test::CliRun bake(const std::string& extra, const std::string& scene = scene_) {
    return test::run_lightbake("bake -q " + scene + " --quality draft " + extra, dir_);
  }
  static test::CliRun shard(int i, int n, const std::string& name, const std::string& extra = "") {
    return bake("--shard " + std::to_string(i) + "/" + std::to_string(n) + " -o " + name + " " +
                extra);
  }
  // `bake EXTRA -o WHOLE`; then the same in n shards NAMEi.pass1 (thread counts differing per
  // shard, as on unequal machines) merged, given in reverse order, into MERGED.
  static void bake_whole_and_in_shards(int n, const std::string& extra, const std::string& whole,
                                       const std::string& merged,
                                       const std::string& scene = scene_) {
    const test::CliRun run = bake(extra + " -o " + whole, scene);
    ASSERT_EQ(run.status, 0) << run.err;
    std::string parts;
    for (int i = 0; i < n; ++i) {
      const std::string part = merged + std::to_string(i) + ".pass1";
      const test::CliRun piece = bake("--shard " + std::to_string(i) + "/" + std::to_string(n) +
                                          " -o " + part + " " + extra + " --threads " +
                                          std::to_string(1 + i % 2),
                                      scene);
      ASSERT_EQ(piece.status, 0) << piece.err;
      parts = part + " " + parts;
    }
    const test::CliRun merge = test::run_lightbake("merge -q " + parts + "-o " + merged, dir_);
    ASSERT_EQ(merge.status, 0) << merge.err;
  }
  static std::vector<float> pixels(const std::string& path) {
    return read_image((fs::path(dir_) / path).string()).pixels;
  }
  static nlohmann::json manifest(const std::string& bake_dir) {
    std::ifstream in(fs::path(dir_) / bake_dir / "manifest.json");
    return nlohmann::json::parse(in);
  }
  static inline std::string dir_, scene_;
};

// What a run measured rather than computed: it differs between any two runs.
void drop_run_measurements(nlohmann::json& manifest) {
  manifest.erase("memory");
  for (const char* pass : {"illumination", "radiosity", "soft_light"}) {
    manifest[pass].erase("seconds");
    if (manifest[pass].contains("stats"))
      for (const char* key :
           {"seconds", "feeler_seconds", "atlas_seconds", "setup_seconds", "pilot_seconds"})
        manifest[pass]["stats"].erase(key);
  }
}

// The merged bake's maps (bit for bit), .bin files and manifest (but for what the runs
// measured) are the whole bake's.
void expect_same_bake(const std::string& dir, const std::string& whole, const std::string& merged,
                      std::initializer_list<const char*> maps,
                      std::initializer_list<const char*> bins) {
  for (const char* map : maps) {
    const std::vector<float> expected = read_image(dir + "/" + whole + "/" + map).pixels;
    ASSERT_FALSE(expected.empty()) << map;
    EXPECT_TRUE(test::same_bits(read_image(dir + "/" + merged + "/" + map).pixels, expected))
        << map;
  }
  for (const char* bin : bins)
    EXPECT_EQ(test::read_bytes(dir + "/" + merged + "/" + bin),
              test::read_bytes(dir + "/" + whole + "/" + bin))
        << bin;
  auto manifest = [&](const std::string& bake) {
    std::ifstream in(fs::path(dir) / bake / "manifest.json");
    nlohmann::json m = nlohmann::json::parse(in);
    drop_run_measurements(m);
    return m;
  };
  const nlohmann::json a = manifest(whole), b = manifest(merged);
  EXPECT_EQ(a, b) << nlohmann::json::diff(a, b).dump();
}

TEST_F(BakeShards, FourShardsMergeToTheBitsOfTheWholeBake) {
  ASSERT_NO_FATAL_FAILURE(bake_whole_and_in_shards(4, "", "whole", "merged"));
  expect_same_bake(dir_, "whole", "merged", {"illumination.exr", "soft_light.exr"},
                   {"illumination.bin", "radiosity.bin"});
  // The caustic is there: the map is not all zeros.
  const std::vector<float> caustic = pixels("whole/illumination.exr");
  EXPECT_GT(*std::max_element(caustic.begin(), caustic.end()), 0.0f);
}

// Light groups ride in the shards (each listed node's power per group after the nodes): the
// merge has the whole bake's group maps and vertex radiance, bit for bit. The box's ceiling
// light (group `default`) and a lamp above the ball (`lamp`) both focus a caustic through it.
TEST_F(BakeShards, LightGroupsMergeToTheBitsOfTheWholeBake) {
  const std::string scene = (fs::path(dir_) / "grouped.toml").string();
  {
    std::ofstream out(scene);
    out << "include = '" << test::source_dir() << "/scenes/cornell_glass.toml'\n"
        << "[[lights]]\ntype = 'point'\nposition = [-0.5, 0.1, 0.5]\npower = 20\n"
        << "group = 'lamp'\n";
  }
  ASSERT_NO_FATAL_FAILURE(
      bake_whole_and_in_shards(3, "", "grouped_whole", "grouped_merged", "'" + scene + "'"));
  EXPECT_EQ(manifest("grouped_whole")["light_groups"].size(), 2u);
  expect_same_bake(dir_, "grouped_whole", "grouped_merged",
                   {"illumination.exr", "soft_light.exr", "group1_illumination.exr",
                    "group2_illumination.exr", "group1_soft_light.exr", "group2_soft_light.exr"},
                   {"illumination.bin", "radiosity.bin", "group1_radiosity.bin",
                    "group2_radiosity.bin"});
  // Both groups' caustics are there: neither map is all zeros.
  for (const char* map : {"group1_illumination.exr", "group2_illumination.exr"}) {
    const std::vector<float> caustic = pixels("grouped_whole/" + std::string(map));
    EXPECT_GT(*std::max_element(caustic.begin(), caustic.end()), 0.0f) << map;
  }
}

// Directional bakes: each listed node's L1 sums ride in the shards too, so the merge has the
// whole bake's caustic band (the glass ball's caustic, the band's only light here) bit for bit.
TEST_F(BakeShards, DirectionalBandsMergeToTheBitsOfTheWholeBake) {
  ASSERT_NO_FATAL_FAILURE(
      bake_whole_and_in_shards(3, "--directional", "directional_whole", "directional_merged"));
  expect_same_bake(dir_, "directional_whole", "directional_merged",
                   {"illumination.exr", "soft_light.exr", "illumination_l1x.exr",
                    "illumination_l1y.exr", "illumination_l1z.exr"},
                   {"illumination.bin", "radiosity.bin"});
  // The band holds the caustic's direction: not all zeros.
  float largest = 0.0f;
  for (const char* axis : {"x", "y", "z"})
    for (float v : pixels("directional_whole/illumination_l1" + std::string(axis) + ".exr"))
      largest = std::max(largest, std::abs(v));
  EXPECT_GT(largest, 0.0f);
}

TEST_F(BakeShards, MergeRefusesIncompleteRepeatedForeignOrAlteredShards) {
  for (int i = 0; i < 2; ++i)
    ASSERT_EQ(shard(i, 2, "half" + std::to_string(i) + ".pass1").status, 0);
  ASSERT_EQ(shard(1, 2, "other_seed.pass1", "--seed 7").status, 0);
  ASSERT_EQ(shard(1, 2, "other_setting.pass1", "--caustic-max-depth 5").status, 0);
  ASSERT_EQ(shard(1, 3, "third.pass1").status, 0);
  const auto error_of = [](const std::string& args) {
    const test::CliRun run = test::run_lightbake("merge -q " + args, dir_);
    EXPECT_NE(run.status, 0) << args;
    EXPECT_FALSE(fs::exists(fs::path(dir_) / "bad")) << args;  // nothing written
    return run.err;
  };
  const auto has = [](const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
  };
  EXPECT_TRUE(has(error_of("half0.pass1 -o bad"), "shard 1 of 2 is missing"));
  EXPECT_TRUE(has(error_of("half0.pass1 half0.pass1 -o bad"), "half0.pass1: shard 0 given twice"));
  EXPECT_TRUE(has(error_of("half0.pass1 other_seed.pass1 -o bad"),
                  "other_seed.pass1: bake.seed 7 differs from half0.pass1's 1: not a shard of "
                  "the same bake"));
  EXPECT_TRUE(has(error_of("half0.pass1 other_setting.pass1 -o bad"),
                  "other_setting.pass1: bake.caustic_max_depth 5 differs from half0.pass1's "
                  "16"));
  EXPECT_TRUE(has(error_of("half0.pass1 third.pass1 -o bad"),
                  "third.pass1: shard_count 3 differs from half0.pass1's 2"));
  EXPECT_TRUE(has(error_of("half0.pass1 other.exr -o bad"), "not both"));
  // Another scene: the one the shards recorded is given elsewhere, with other contents.
  const std::string box = "'" + test::source_dir() + "/scenes/cornell_box.toml'";
  EXPECT_TRUE(has(error_of("half0.pass1 half1.pass1 --scene " + box + " -o bad"),
                  "differs from the shards'"));
  // A shard whose data is not the data its report describes.
  fs::copy_file(fs::path(dir_) / "half1.pass1", fs::path(dir_) / "altered.pass1",
                fs::copy_options::overwrite_existing);
  fs::copy_file(fs::path(dir_) / "half1.json", fs::path(dir_) / "altered.json",
                fs::copy_options::overwrite_existing);
  {
    std::fstream data(fs::path(dir_) / "altered.pass1",
                      std::ios::in | std::ios::out | std::ios::binary);
    data.seekp(40);
    data.put('\x7f');
  }
  EXPECT_TRUE(has(error_of("half0.pass1 altered.pass1 -o bad"),
                  "altered.pass1: its size or FNV-1a differs from"));
}

TEST_F(BakeShards, AShardWritesOnlyWhatItOwns) {
  // Refused before any work: a name that is not .pass1, an index outside its count, a file
  // lightbake did not write.
  EXPECT_TRUE(shard(0, 2, "s.exr").err.find("a pass-1 shard is written as .pass1") !=
              std::string::npos);
  EXPECT_TRUE(shard(2, 2, "s.pass1").err.find("--shard 2/2: needs 0 <= INDEX < COUNT") !=
              std::string::npos);
  { std::ofstream(fs::path(dir_) / "notes.pass1") << "mine\n"; }
  const test::CliRun refused = shard(0, 2, "notes.pass1");
  EXPECT_NE(refused.status, 0);
  EXPECT_NE(refused.err.find("notes.pass1: exists and was not written by lightbake"),
            std::string::npos)
      << refused.err;
  EXPECT_EQ(test::read_bytes(dir_ + "/notes.pass1"), "mine\n");
  EXPECT_FALSE(fs::exists(fs::path(dir_) / "notes.json"));
  // Its own earlier shard it replaces.
  ASSERT_EQ(shard(0, 2, "again.pass1").status, 0);
  EXPECT_EQ(shard(0, 2, "again.pass1").status, 0);
}

}  // namespace
}  // namespace lb
