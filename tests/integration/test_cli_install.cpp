// `cmake --install` and the installed lightbake: it runs from a directory outside the source
// tree without opening any file of it (the shaders are compiled in, cmake/EmbedShaders.cmake;
// the image plugin comes from the prefix), and draws the same bits as the build tree's binary
// reading the shaders from shaders/.

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <sstream>
#include <string>

#include "bake/io/image_io.h"
#include "test_helpers.h"

namespace lb {
namespace {

namespace fs = std::filesystem;

// A temporary install prefix outside the source tree (the build tree is inside it), removed
// when the test ends.
struct TemporaryPrefix {
  fs::path path = fs::temp_directory_path() / ("lightbake-install-" + std::to_string(::getpid()));
  TemporaryPrefix() { fs::remove_all(path); }
  ~TemporaryPrefix() { fs::remove_all(path); }
};

TEST(Install, InstalledBinaryRunsFromAnywhereWithoutTheSourceTree) {
  const std::string source = test::source_dir();
  const TemporaryPrefix prefix;
  const test::CliRun install =
      test::run_command(std::string("'") + LIGHTBAKE_CMAKE_COMMAND + "' --install '" +
                        LIGHTBAKE_BINARY_DIR + "' --prefix '" + prefix.path.string() + "'");
  ASSERT_EQ(install.status, 0) << install.out << install.err;
  // The executable and its image plugin are all that is installed, and all that the run below
  // needs.
  int installed_files = 0;
  for (const auto& entry : fs::recursive_directory_iterator(prefix.path))
    installed_files += entry.is_regular_file();
  EXPECT_EQ(installed_files, 2);
  const fs::path binary = prefix.path / "bin" / "lightbake";
  ASSERT_TRUE(fs::exists(binary));
  const fs::path plugin = prefix.path / LIGHTBAKE_INSTALL_PLUGIN_DIR / "lightbake_images.so";
  ASSERT_TRUE(fs::exists(plugin));

  // A working directory in /tmp holding a copy of the scene (it names no other file).
  const fs::path work = prefix.path / "work";
  fs::create_directories(work);
  fs::copy_file(source + "/scenes/cornell_box.toml", work / "cornell_box.toml");

  // strace lists every path the process and its threads look up; LeakSanitizer cannot run
  // under ptrace, so the sanitizer build skips its leak check for this one run.
  ASSERT_EQ(test::run_command("strace -V").status, 0) << "strace missing: run scripts/setup.sh";
  const test::CliRun run =
      test::run_command("ASAN_OPTIONS=detect_leaks=0 strace -f -qq -e trace=%file -o trace.txt '" +
                            binary.string() + "' snapshot cornell_box.toml --no-bake -o x.png",
                        work.string());
  ASSERT_EQ(run.status, 0) << run.err;
  std::istringstream trace(test::read_bytes(work / "trace.txt"));
  int traced = 0, into_source = 0, plugin_opened = 0;
  for (std::string line; std::getline(trace, line); ++traced) {
    if (line.find(source + "/") != std::string::npos) {
      ++into_source;
      ADD_FAILURE() << "the installed binary looked into the source tree: " << line;
    }
    plugin_opened += line.find(plugin.string() + "\"") != std::string::npos &&
                     line.find("openat(") != std::string::npos && line.find(" = -1") == line.npos;
  }
  EXPECT_GT(traced, 20);  // the trace did record the run (684 path calls when written)
  EXPECT_EQ(into_source, 0);
  EXPECT_EQ(plugin_opened, 1) << "the PNG is written through the installed image plugin";

  // The image: 640 x 480 PNG; the red wall red, the green wall green, the light white (values
  // in [0,1] as read; measured 0.42/0.027, 0.12/0.28 and 1.0 when written).
  const Image image = read_image((work / "x.png").string());
  ASSERT_EQ(image.width, 640);
  ASSERT_EQ(image.height, 480);
  EXPECT_GT(image.at(120, 240, 0), 5.0f * image.at(120, 240, 1));
  EXPECT_GT(image.at(520, 200, 1), 1.5f * image.at(520, 200, 0));
  EXPECT_GT(image.at(320, 68, 1), 0.99f);

  // Bit for bit what the build tree's binary draws reading the shaders from the source tree.
  const fs::path dev = prefix.path / "dev.png";
  const test::CliRun from_source =
      test::run_lightbake("snapshot cornell_box.toml --no-bake --shaders '" + source +
                              "/shaders' -o '" + dev.string() + "'",
                          work.string());
  ASSERT_EQ(from_source.status, 0) << from_source.err;
  EXPECT_TRUE(test::read_bytes(work / "x.png") == test::read_bytes(dev));
}

TEST(Install, ShadersFromAMissingDirectoryFailInOneLineNamingTheFile) {
  const fs::path dir = test::fresh_dir("install", "missing_shaders");
  const test::CliRun run = test::run_lightbake(
      "snapshot '" + test::source_dir() + "/scenes/cornell_box.toml' --no-bake --shaders '" +
      (dir / "none").string() + "' -o '" + (dir / "x.png").string() + "'");
  EXPECT_NE(run.status, 0);
  EXPECT_NE(run.err.find((dir / "none").string() + "/"), std::string::npos) << run.err;
  EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
  EXPECT_FALSE(fs::exists(dir / "x.png"));
}

}  // namespace
}  // namespace lb
