// `--threads N` changes how long a subcommand takes, never its output: bake, render,
// reference, export (also with --denoise) and snapshot run with 1 and 2 threads (all this
// machine's cores; a different count splits TBB's loops differently) write the same bits,
// timings aside.

#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "bake/io/image_io.h"
#include "test_helpers.h"

namespace lb {
namespace {

namespace fs = std::filesystem;

// The JSON without its measurements of the run (every key that names seconds, and the peak
// resident memory), which are the only ones allowed to differ between two runs.
nlohmann::json without_measurements(nlohmann::json json) {
  if (json.is_object()) {
    nlohmann::json kept = nlohmann::json::object();
    for (auto& [key, value] : json.items())
      if (key.find("second") == std::string::npos && key != "peak_resident_bytes")
        kept[key] = without_measurements(value);
    return kept;
  }
  if (json.is_array())
    for (auto& value : json) value = without_measurements(value);
  return json;
}

// The same bytes, and there are some (a missing file reads as empty).
bool same_bytes(const fs::path& a, const fs::path& b) {
  const std::string x = test::read_bytes(a);
  return !x.empty() && x == test::read_bytes(b);
}

nlohmann::json read_json(const fs::path& path) {
  return without_measurements(nlohmann::json::parse(test::read_bytes(path)));
}

bool same_pixels(const fs::path& a, const fs::path& b) {
  const Image x = read_image(a.string()), y = read_image(b.string());
  return !x.empty() && x.width == y.width && x.height == y.height && x.channels == y.channels &&
         test::same_bits(x.pixels, y.pixels);
}

// Every subcommand run once per thread count, each in its own folder with the same relative
// output names, so reports that quote their output path agree too.
class ThreadCount : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    // Appended, not summed: GCC 12's -Wrestrict misfires on `"literal" + std::string` here.
    std::string scene = "'";
    scene += test::source_dir();
    scene += "/scenes/cornell_glass.toml'";
    for (int threads : {1, 2}) {
      const fs::path dir = test::fresh_dir("cli_threads", std::to_string(threads));
      std::string t = " -q --threads ";
      t += std::to_string(threads);
      for (const std::string& args :
           {"bake " + scene + " -o bake" + t,
            "render " + scene + " bake --size 96x72 --spp 4 -o render.exr" + t,
            "reference " + scene + " --size 48x36 --spp 4 -o reference.exr" + t,
            "export " + scene + " bake --contents all --direct-samples 2 -o scene.glb" + t,
            "export " + scene + " bake --contents all --direct-samples 2 --denoise -o denoised.glb" +
                t,
            "snapshot " + scene + " bake --size 160x120 -o snapshot.png" + t}) {
        const test::CliRun run = test::run_lightbake(args, dir.string());
        ASSERT_EQ(run.status, 0) << args << "\n" << run.err;
      }
    }
  }
  static fs::path one(const std::string& file) {
    return fs::path(test::output_dir()) / "cli_threads" / "1" / file;
  }
  static fs::path two(const std::string& file) {
    return fs::path(test::output_dir()) / "cli_threads" / "2" / file;
  }
};

// One test, so the twelve runs happen once (ctest runs each test in its own process).
TEST_F(ThreadCount, EverySubcommandWritesTheSameBitsWithOneOrTwoThreads) {
  EXPECT_TRUE(same_bytes(one("bake/illumination.bin"), two("bake/illumination.bin")));
  EXPECT_TRUE(same_bytes(one("bake/radiosity.bin"), two("bake/radiosity.bin")));
  EXPECT_TRUE(same_pixels(one("bake/illumination.exr"), two("bake/illumination.exr")));
  const nlohmann::json manifest = read_json(one("bake/manifest.json"));
  EXPECT_EQ(manifest, read_json(two("bake/manifest.json")));
  // The bake did trace the glass ball's caustic, so equal maps are not empty ones (458752
  // illumination rays depositing 0.156 W of red when written).
  EXPECT_GT(manifest["illumination"]["stats"]["illumination_rays"].get<double>(), 1e5);
  EXPECT_GT(manifest["illumination"]["stats"]["power_deposited"][0].get<double>(), 0.1);

  EXPECT_TRUE(same_pixels(one("render.exr"), two("render.exr")));
  EXPECT_EQ(read_json(one("render.json")), read_json(two("render.json")));
  EXPECT_TRUE(same_pixels(one("reference.exr"), two("reference.exr")));
  EXPECT_EQ(read_json(one("reference.json")), read_json(two("reference.json")));
  EXPECT_TRUE(same_bytes(one("scene.glb"), two("scene.glb")));
  EXPECT_TRUE(same_pixels(one("scene.lightmap.exr"), two("scene.lightmap.exr")));
  // Open Image Denoise (export --denoise) included: it runs on the same TBB.
  EXPECT_TRUE(same_bytes(one("denoised.glb"), two("denoised.glb")));
  EXPECT_TRUE(same_pixels(one("denoised.lightmap.exr"), two("denoised.lightmap.exr")));
  EXPECT_FALSE(same_pixels(one("denoised.lightmap.exr"), one("scene.lightmap.exr")));
  EXPECT_TRUE(same_bytes(one("snapshot.png"), two("snapshot.png")));
}

TEST(ThreadOption, RejectsANegativeCount) {
  const test::CliRun run =
      test::run_lightbake("bake '" + test::source_dir() + "/scenes/cornell_box.toml' --threads -1");
  EXPECT_NE(run.status, 0);
  EXPECT_NE(run.err.find("--threads"), std::string::npos) << run.err;
}

}  // namespace
}  // namespace lb
