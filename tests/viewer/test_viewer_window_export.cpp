// The viewer's Export button (viewer/export_job.h) in the GLFW window under Xvfb, pressed by
// the `--export PATH` automation hook: the file it writes is byte for byte the one
// `lightbake export` writes from the same scene (the bake is deterministic), whether the
// window baked first or the export job did (--no-bake); it is a valid lightbake glTF; and the
// CLI's output rules hold: a file lightbake did not write is never replaced, a missing folder
// is refused, each with the error line and status 1.

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

#include "bake/export/gltf_export.h"
#include "bake/io/scene_load.h"
#include "test_helpers.h"

namespace lb {
namespace {

namespace fs = std::filesystem;

std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

struct ViewRun {
  int status = -1;
  std::string out, err;
};

// `lightbake view SCENE ARGS` under Xvfb with a small window.
ViewRun run_view(const std::string& scene, const std::string& args, const fs::path& dir) {
  const std::string out = (dir / "view.out").string(), err = (dir / "view.err").string();
  std::string command = test::xvfb_lightbake_command("view '");
  command.append(test::source_dir());
  command.append("/scenes/").append(scene).append("' --size 320x240 --frames 2 ").append(args);
  command.append(" > '").append(out).append("' 2> '").append(err).append("'");
  ViewRun run;
  const int status = std::system(command.c_str());
  run.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  run.out = read_file(out);
  run.err = read_file(err);
  return run;
}

void expect_same_file_as_cli(const std::string& scene, const std::string& view_args,
                             const std::string& name) {
  const fs::path dir = test::fresh_dir("viewer_export", name);
  fs::create_directories(dir / "cli");
  const ViewRun view =
      run_view(scene, view_args + " --export '" + (dir / "out.glb").string() + "'", dir);
  ASSERT_EQ(view.status, 0) << view.err;
  EXPECT_NE(view.out.find("exported "), std::string::npos) << view.out;
  ASSERT_TRUE(fs::exists(dir / "out.glb"));
  EXPECT_TRUE(is_lightbake_gltf((dir / "out.glb").string()));

  const std::string source = test::source_dir() + "/scenes/" + scene;
  ASSERT_EQ(test::run_lightbake("export -q '" + source + "' -o cli/out.glb", dir.string()).status,
            0);
  const std::string window_bytes = read_file(dir / "out.glb");
  EXPECT_EQ(window_bytes.size(), fs::file_size(dir / "cli" / "out.glb"));
  EXPECT_TRUE(window_bytes == read_file(dir / "cli" / "out.glb")) << "differs from the CLI's";
  EXPECT_EQ(fs::exists(dir / "out.lightmap.exr"), fs::exists(dir / "cli" / "out.lightmap.exr"));

  // Valid: our loader reads it back with every mesh, and the Khronos validator (when
  // scripts/test.sh installed it; gltf_export_validator runs it on the CLI's files anyway).
  const LoadResult back = load_scene((dir / "out.glb").string());
  EXPECT_EQ(back.scene.meshes.size(), load_scene(source).scene.meshes.size());
  const std::string modules = std::string(LIGHTBAKE_BINARY_DIR) + "/npm/node_modules";
  if (std::system("command -v node > /dev/null") == 0 && fs::exists(modules + "/gltf-validator")) {
    std::string validate = "NODE_PATH='" + modules + "' node '";
    validate.append(test::source_dir()).append("/scripts/validate_gltf.js' '");
    validate.append((dir / "out.glb").string()).append("' > /dev/null");
    EXPECT_EQ(std::system(validate.c_str()), 0) << validate;
  }
}

TEST(ViewerWindowExport, AfterTheWindowsBakeWritesWhatTheCliWrites) {
  if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "xvfb-run is not installed (Debian package xvfb)";
  expect_same_file_as_cli("fig3_ring.toml", "", "fig3_ring");  // with a caustic map + EXR
}

TEST(ViewerWindowExport, WithoutABakeTheJobBakesFirst) {
  if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "xvfb-run is not installed (Debian package xvfb)";
  expect_same_file_as_cli("cornell_box.toml", "--no-bake", "cornell_box");
}

TEST(ViewerWindowExport, RefusesForeignFilesAndMissingFolders) {
  if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "xvfb-run is not installed (Debian package xvfb)";
  const fs::path dir = test::fresh_dir("viewer_export", "refusals");
  const std::string foreign = "an artist's model, not ours";
  std::ofstream(dir / "mine.glb") << foreign;
  const ViewRun refused =
      run_view("cornell_box.toml", "--no-bake --export '" + (dir / "mine.glb").string() + "'", dir);
  EXPECT_EQ(refused.status, 1);
  EXPECT_NE(refused.err.find("mine.glb: exists and was not written by lightbake"),
            std::string::npos)
      << refused.err;
  EXPECT_EQ(read_file(dir / "mine.glb"), foreign);
  EXPECT_FALSE(fs::exists(dir / "mine.lightmap.exr"));

  const ViewRun missing =
      run_view("cornell_box.toml",
               "--no-bake --export '" + (dir / "no_such" / "out.glb").string() + "'", dir);
  EXPECT_EQ(missing.status, 1);
  EXPECT_NE(missing.err.find("does not exist"), std::string::npos) << missing.err;
  EXPECT_FALSE(fs::exists(dir / "no_such"));
}

}  // namespace
}  // namespace lb
