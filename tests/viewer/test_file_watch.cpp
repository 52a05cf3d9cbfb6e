// FileWatch, the viewer's reload-on-save: a rewrite is one change, a missing file none, its
// return one.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "test_helpers.h"
#include "viewer/file_watch.h"

namespace lb {
namespace {

namespace fs = std::filesystem;

TEST(FileWatch, ARewriteIsOneChangeAMissingFileNone) {
  const fs::path dir = test::fresh_dir("file_watch", "rewrite");
  const fs::path path = dir / "scene.toml";
  std::ofstream(path) << "a = 1\n";
  FileWatch watch;
  watch.watch(path.string());
  EXPECT_FALSE(watch.changed());
  // The same size, a later time (as an editor's save within the same second may not give).
  std::ofstream(path) << "a = 2\n";
  fs::last_write_time(path, fs::last_write_time(path) + std::chrono::seconds(2));
  EXPECT_TRUE(watch.changed());
  EXPECT_FALSE(watch.changed());  // once per change
  fs::remove(path);
  EXPECT_FALSE(watch.changed());  // gone: no change (an editor may delete, then write)
  std::ofstream(path) << "a = 3 # back\n";
  EXPECT_TRUE(watch.changed());
  EXPECT_FALSE(watch.changed());
  // An empty watch never changes.
  FileWatch none;
  EXPECT_FALSE(none.changed());
}

}  // namespace
}  // namespace lb
