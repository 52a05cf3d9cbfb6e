// The viewer's Export button (viewer/export_job.h) in the GLFW window under Xvfb, pressed by
// the `--export PATH` automation hook: the file it writes is byte for byte the one
// `lightbake export` writes from the same scene (the bake is deterministic), whether the
// window baked first or the export job did (--no-bake), and with a moving object (the light
// probes); it is a valid lightbake glTF; and the CLI's output rules hold: a file lightbake did
// not write is never replaced, a missing folder is refused, each with the error line and
// status 1.

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

#include "bake/export/gltf_export.h"
#include "bake/io/gltf_directional.h"
#include "bake/io/scene_load.h"
#include "bake/probe_grid.h"
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

// `lightbake view SCENE ARGS` under Xvfb with a small window; SCENE relative to the sources.
ViewRun run_view(const std::string& scene, const std::string& args, const fs::path& dir) {
  const std::string out = (dir / "view.out").string(), err = (dir / "view.err").string();
  std::string command = test::xvfb_lightbake_command("view '");
  command.append(test::source_dir());
  command.append("/").append(scene).append("' --size 320x240 --frames 2 ").append(args);
  command.append(" > '").append(out).append("' 2> '").append(err).append("'");
  ViewRun run;
  const int status = std::system(command.c_str());
  run.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  run.out = read_file(out);
  run.err = read_file(err);
  return run;
}

// `bake_args` go to both the window and `lightbake export`.
void expect_same_file_as_cli(const std::string& scene, const std::string& view_args,
                             const std::string& name, const std::string& bake_args = "") {
  const fs::path dir = test::fresh_dir("viewer_export", name);
  fs::create_directories(dir / "cli");
  const ViewRun view =
      run_view(scene, view_args + bake_args + " --export '" + (dir / "out.glb").string() + "'",
               dir);
  ASSERT_EQ(view.status, 0) << view.err;
  EXPECT_NE(view.out.find("exported "), std::string::npos) << view.out;
  ASSERT_TRUE(fs::exists(dir / "out.glb"));
  EXPECT_TRUE(is_lightbake_gltf((dir / "out.glb").string()));

  const std::string source = test::source_dir() + "/" + scene;
  ASSERT_EQ(test::run_lightbake("export -q '" + source + "' -o cli/out.glb" + bake_args,
                                dir.string())
                .status,
            0);
  const std::string window_bytes = read_file(dir / "out.glb");
  EXPECT_EQ(window_bytes.size(), fs::file_size(dir / "cli" / "out.glb"));
  EXPECT_TRUE(window_bytes == read_file(dir / "cli" / "out.glb")) << "differs from the CLI's";
  EXPECT_EQ(fs::exists(dir / "out.lightmap.exr"), fs::exists(dir / "cli" / "out.lightmap.exr"));

  // Valid: our loader reads it back with every mesh, and the Khronos validator (when
  // scripts/test.sh installed it; gltf_export_validator runs it on the CLI's files anyway).
  const LoadResult back = load_scene((dir / "out.glb").string());
  const Scene given = load_scene(source).scene;
  EXPECT_EQ(back.scene.meshes.size(), given.meshes.size());
  EXPECT_EQ(back.scene.dynamic_meshes.size(), given.dynamic_meshes.size());
  // Moving objects: the probe grid and each object's blend of it (docs/light-probes.md).
  const bool probes = window_bytes.find("\"LIGHTBAKE_light_probes\"") != std::string::npos;
  EXPECT_EQ(probes, !given.dynamic_meshes.empty());
  for (const Mesh& mesh : back.scene.dynamic_meshes)
    EXPECT_EQ(mesh.probe_sh.size(), size_t(kShCoefficients)) << mesh.name;
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
  expect_same_file_as_cli("scenes/fig3_ring.toml", "", "fig3_ring");  // a caustic map + EXR
}

TEST(ViewerWindowExport, WithoutABakeTheJobBakesFirst) {
  if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "xvfb-run is not installed (Debian package xvfb)";
  expect_same_file_as_cli("scenes/cornell_box.toml", "--no-bake", "cornell_box");
}

// A moving object: the window writes the probe grid and the object's light as the CLI does
// (a draft bake: the probes are baked whole at every quality, and they are what is tested).
TEST(ViewerWindowExport, WritesTheLightProbesOfAMovingObject) {
  if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "xvfb-run is not installed (Debian package xvfb)";
  expect_same_file_as_cli("tests/data/scene/cornell_dynamic.toml", "", "cornell_dynamic",
                          " --quality draft");
}

// A view of a directional bake (`view --directional`: the bake's bands drawn) exports its
// directional maps, as `lightbake export --directional` does; a plain view's export has none
// (the tests above).
TEST(ViewerWindowExport, ADirectionalViewWritesDirectionalMaps) {
  if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "xvfb-run is not installed (Debian package xvfb)";
  expect_same_file_as_cli("scenes/studded_wall.toml", "", "studded_wall", " --directional");
  const std::string file =
      read_file(fs::path(test::output_dir()) / "viewer_export" / "studded_wall" / "out.glb");
  EXPECT_NE(file.find(kDirectionalExtension), std::string::npos);  // the glb's JSON chunk
}

// The panel's export options are the command line's (ExportSettings, one struct for both):
// `view --contents all --lightmap-encoding rgbm` writes what `lightbake export` writes with
// them, an RGBM map (4 channels, the extras naming rgbm8) that holds the direct light.
TEST(ViewerWindowExport, ThePanelsOptionsAreTheCommandLines) {
  if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "xvfb-run is not installed (Debian package xvfb)";
  expect_same_file_as_cli("scenes/cornell_box.toml", "--no-bake", "cornell_box_rgbm",
                          " --texel-density 10 --contents all --lightmap-encoding rgbm");
  const std::string path = (fs::path(test::output_dir()) / "viewer_export" /
                            "cornell_box_rgbm" / "out.glb")
                               .string();
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string err, warn;
  ASSERT_TRUE(loader.LoadBinaryFromFile(&model, &err, &warn, path)) << err;
  const auto map = std::find_if(model.images.begin(), model.images.end(),
                                [](const tinygltf::Image& i) { return i.name == "lightmap"; });
  ASSERT_NE(map, model.images.end());
  EXPECT_EQ(map->component, 4);
  ASSERT_FALSE(model.materials.empty());
  const tinygltf::Value& extras = model.materials[0].extras.Get("lightbake_lightmap");
  EXPECT_EQ(extras.Get("encoding").Get<std::string>(), "rgbm8");
  EXPECT_TRUE(extras.Get("includes_direct").Get<bool>());
  // A refusal is the command line's too, before any bake: one line, status 1, nothing written.
  const fs::path dir = test::fresh_dir("viewer_export", "panel_refusal");
  const ViewRun refused = run_view(
      "scenes/cornell_box.toml",
      "--no-bake --denoise --export '" + (dir / "out.glb").string() + "'", dir);
  EXPECT_EQ(refused.status, 1);
  EXPECT_NE(refused.err.find("--denoise: only the direct term of --contents all"),
            std::string::npos)
      << refused.err;
  EXPECT_FALSE(fs::exists(dir / "out.glb"));
}

TEST(ViewerWindowExport, RefusesForeignFilesAndMissingFolders) {
  if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "xvfb-run is not installed (Debian package xvfb)";
  const fs::path dir = test::fresh_dir("viewer_export", "refusals");
  const std::string foreign = "an artist's model, not ours";
  std::ofstream(dir / "mine.glb") << foreign;
  const ViewRun refused =
      run_view("scenes/cornell_box.toml",
               "--no-bake --export '" + (dir / "mine.glb").string() + "'", dir);
  EXPECT_EQ(refused.status, 1);
  EXPECT_NE(refused.err.find("mine.glb: exists and was not written by lightbake"),
            std::string::npos)
      << refused.err;
  EXPECT_EQ(read_file(dir / "mine.glb"), foreign);
  EXPECT_FALSE(fs::exists(dir / "mine.lightmap.exr"));

  const ViewRun missing =
      run_view("scenes/cornell_box.toml",
               "--no-bake --export '" + (dir / "no_such" / "out.glb").string() + "'", dir);
  EXPECT_EQ(missing.status, 1);
  EXPECT_NE(missing.err.find("does not exist"), std::string::npos) << missing.err;
  EXPECT_FALSE(fs::exists(dir / "no_such"));
}

}  // namespace
}  // namespace lb
