// The shard container every sharded command writes (bake/shards/shard_file.h): a set of shards
// reads back in index order with its payloads, and what is not one run's complete, intact set of
// one kind is refused in one line that names the file.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "bake/shards/shard_file.h"
#include "test_helpers.h"

namespace lb::shards {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr ShardKind kSums{ShardTag::pass1,    "sums", "a sums shard", "test sums", ".sums",
                          "test",             "test run", 3};
constexpr ShardKind kOther{ShardTag::reference, "other", "an other shard", "test", ".other",
                           "other",              "other run", 3};

class ShardFileTest : public testing::Test {
 protected:
  // A folder for each test: ctest runs this suite's tests in parallel processes.
  void SetUp() override {
    const auto* info = testing::UnitTest::GetInstance()->current_test_info();
    dir_ = test::fresh_dir("shards", std::string("shard_file_") + info->name());
  }
  std::string path(const std::string& name) const { return (fs::path(dir_) / name).string(); }
  // Shard `index` of `count`: payload the bytes 10 * index + k, k < 5.
  std::string write(const std::string& name, int index, int count, json settings = {},
                    const ShardKind& kind = kSums) const {
    std::vector<std::byte> payload;
    for (int k = 0; k < 5; ++k) payload.push_back(std::byte(10 * index + k));
    if (settings.is_null()) settings = {{"seed", 1}, {"tone", {{"curve", "aces"}}}};
    write_shard(path(name), kind, index, count, payload, "scene.toml", settings,
                {{"seconds", 0.5}});
    return path(name);
  }
  // The message of the error `f` throws ("" if none).
  template <class F>
  static std::string error_of(F f) {
    try {
      f();
    } catch (const std::runtime_error& e) {
      return e.what();
    }
    return "";
  }
  std::string dir_;
};

TEST_F(ShardFileTest, ASetReadsBackInIndexOrderWithItsPayloads) {
  const std::vector<std::string> paths = {write("b.sums", 2, 3), write("a.sums", 0, 3),
                                          write("c.sums", 1, 3)};
  EXPECT_TRUE(is_shard_file(paths[0]));
  const std::vector<ShardFile> set = read_shard_set(paths, kSums);
  ASSERT_EQ(set.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(set[size_t(i)].index, i);
    EXPECT_EQ(set[size_t(i)].settings().at("shard_count"), 3);
    EXPECT_EQ(set[size_t(i)].report.at("seconds"), 0.5);
    Reader r = open_shard_payload(set[size_t(i)], kSums);
    for (int k = 0; k < 5; ++k) EXPECT_EQ(r.get<uint8_t>(), 10 * i + k);
    r.expect_end();
  }
  EXPECT_EQ(set[0].data_path, paths[1]);
  EXPECT_EQ(set[0].report.at("data").at("bytes"), 24 + 5);  // header, payload
}

TEST_F(ShardFileTest, DamagedOrForeignDataIsRefusedNamingTheFile) {
  const ShardFile intact = read_shard_report(write("s.sums", 0, 1), kSums);
  const std::string bytes = test::read_bytes(intact.data_path);
  // A truncated payload and a flipped byte: the report's size and FNV-1a do not match.
  std::ofstream(intact.data_path, std::ios::binary) << bytes.substr(0, bytes.size() - 1);
  EXPECT_NE(error_of([&] { open_shard_payload(intact, kSums); })
                .find("s.sums: its size or FNV-1a differs from " + intact.report_path),
            std::string::npos);
  std::string flipped = bytes;
  flipped[26] ^= 1;
  std::ofstream(intact.data_path, std::ios::binary) << flipped;
  EXPECT_NE(error_of([&] { open_shard_payload(intact, kSums); }).find("s.sums: its size or FNV-1a"),
            std::string::npos);
  // A report of another kind, and the header of another kind under a report that vouches for it.
  EXPECT_NE(error_of([&] { read_shard_report(write("o.other", 0, 1, {}, kOther), kSums); })
                .find("o.json: not the report of a `lightbake test --shard` run of this version "
                      "(3)"),
            std::string::npos);
  ShardFile forged = read_shard_report(path("o.other"), kOther);
  forged.report["kind"] = kSums.name;
  EXPECT_NE(error_of([&] { open_shard_payload(forged, kSums); })
                .find("o.other: at byte 12: not a sums shard"),
            std::string::npos);
  // A report of the formats before the container, at the kind's version.
  std::ofstream(path("old.json")) << json{{"format", "lightbake-pass1-shard"},
                                          {"version", 3},
                                          {"shard", {{"index", 0}, {"count", 1}}},
                                          {"settings", json::object()}}
                                         .dump();
  EXPECT_NE(error_of([&] { read_shard_report(path("old.sums"), kSums); })
                .find("old.json: not the report of a `lightbake test --shard` run of this version"),
            std::string::npos);
  // Not a shard at all, and a data file without its report.
  std::ofstream(path("plain.sums")) << "notes";
  EXPECT_FALSE(is_shard_file(path("plain.sums")));
  EXPECT_NE(error_of([&] { read_shard_report(path("plain.sums"), kSums); })
                .find("plain.json: cannot read the shard's report"),
            std::string::npos);
  EXPECT_NE(error_of([&] { check_shard_extension(path("x.exr"), kSums); })
                .find("x.exr: a sums shard is written as .sums (test sums)"),
            std::string::npos);
  EXPECT_EQ(error_of([&] { check_shard_extension(path("x.SUMS"), kSums); }), "");
}

TEST_F(ShardFileTest, OnlyACompleteSetOfOneRunIsASet) {
  const std::string a = write("a.sums", 0, 2), b = write("b.sums", 1, 2);
  EXPECT_EQ(error_of([&] { read_shard_set({a}, kSums); }), "shard 1 of 2 is missing");
  EXPECT_NE(error_of([&] { read_shard_set({a, b, a}, kSums); })
                .find("a.sums: shard 0 given twice (also " + a + ")"),
            std::string::npos);
  // Settings compared key by key, into objects: the first that differs, both values, both files.
  const std::string seed = write("seed.sums", 1, 2, {{"seed", 7}, {"tone", {{"curve", "aces"}}}});
  EXPECT_EQ(error_of([&] { read_shard_set({a, seed}, kSums); }),
            seed + ": seed 7 differs from " + a + "'s 1: not a shard of the same test run");
  const std::string tone = write("tone.sums", 1, 2, {{"seed", 1}, {"tone", {{"curve", "clamp"}}}});
  EXPECT_EQ(error_of([&] { read_shard_set({a, tone}, kSums); }),
            tone + ": tone.curve \"clamp\" differs from " + a +
                "'s \"aces\": not a shard of the same test run");
  const std::string third = write("third.sums", 1, 3);
  EXPECT_NE(error_of([&] { read_shard_set({a, third}, kSums); })
                .find("third.sums: shard_count 3 differs from " + a + "'s 2"),
            std::string::npos);
  EXPECT_EQ(error_of([&] { read_shard_set({b, a}, kSums); }), "");
}

}  // namespace
}  // namespace lb::shards
