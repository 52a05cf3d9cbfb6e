// Replays every file of fuzz/corpus/<target>/ through the target's entry function in the normal
// build: what the fuzzers found (and the project's own bad files) must load or be refused,
// never crash, hang or throw anything else.

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "fuzz/fuzz_targets.h"

namespace lb {
namespace {

namespace fs = std::filesystem;

// Each input must finish within this (the bound is 20 s; the slowest seed takes ~0.3 s).
constexpr double kSecondsPerInput = 20.0;

void replay(const std::string& target, int (*entry)(const uint8_t*, size_t)) {
  const fs::path dir = fs::path(LIGHTBAKE_FUZZ_CORPUS) / target;
  ASSERT_TRUE(fs::is_directory(dir)) << dir;
  int inputs = 0;
  for (const auto& entry_file : fs::directory_iterator(dir)) {
    std::ifstream in(entry_file.path(), std::ios::binary);
    std::stringstream bytes;
    bytes << in.rdbuf();
    const std::string data = bytes.str();
    const auto start = std::chrono::steady_clock::now();
    EXPECT_NO_THROW(entry(reinterpret_cast<const uint8_t*>(data.data()), data.size()))
        << entry_file.path();
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_LT(seconds, kSecondsPerInput) << entry_file.path();
    ++inputs;
  }
  EXPECT_GT(inputs, 0) << "empty corpus " << dir;
}

TEST(FuzzCorpus, Toml) {
  replay("toml", fuzz_toml);
}
TEST(FuzzCorpus, Gltf) {
  replay("gltf", fuzz_gltf);
}
TEST(FuzzCorpus, Obj) {
  replay("obj", fuzz_obj);
}
TEST(FuzzCorpus, Ply) {
  replay("ply", fuzz_ply);
}
TEST(FuzzCorpus, Stl) {
  replay("stl", fuzz_stl);
}
TEST(FuzzCorpus, BakeDir) {
  replay("bake_dir", fuzz_bake_dir);
}

}  // namespace
}  // namespace lb
