// A bake started in the GLFW window (under Xvfb): partial results are shown while it refines,
// it still completes, and the final frame equals an OSMesa render of the same bake made here
// with the same params (the bake is deterministic, so the maps are the same bits): every
// channel of every pixel within 1.5/255, as in test_viewer_window.

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "bake/io/image_io.h"
#include "bake/io/scene_load.h"
#include "bake/pipeline/bake.h"
#include "test_helpers.h"
#include "viewer/offscreen_context.h"
#include "viewer/renderer.h"
#include "viewer/snapshot.h"
#include "viewer_test_scenes.h"

namespace lb {
namespace {

TEST(ViewerWindowBake, BakeInWindowCompletesAndEqualsOffscreenRenderOfSameBake) {
  if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "xvfb-run is not installed (Debian package xvfb)";
  const std::string scene_path = test::source_dir() + "/scenes/room.toml";
  const std::string screenshot = test::output_dir() + "/window_bake_room.png";
  const std::string log = test::output_dir() + "/window_bake_room.log";
  std::filesystem::remove(screenshot);
  // No BAKE_DIR and no --no-bake: the window bakes with the default BakeParams.
  const std::string command = test::xvfb_lightbake_command(
      "view " + scene_path + " --size 320x240 --exposure -2.5 --hide-panel " +
      "--frames 3 --screenshot " + screenshot + " > " + log);
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  std::stringstream output;
  output << std::ifstream(log).rdbuf();
  // The window reports the finished bake (how many partials it showed depends on timing).
  EXPECT_NE(output.str().find("baked: "), std::string::npos) << output.str();
  std::printf("%s", output.str().c_str());
  ASSERT_TRUE(std::filesystem::exists(screenshot));
  const Image window = read_image(screenshot, ImageDecode::as_stored);

  // The window drew the scene unbaked first (set_scene), then swapped each partial and the
  // final bake in (update_scene, which keeps the shadow cubes of the first): render the final
  // bake offscreen the same way. (set_scene with the bake from the start differs slightly at
  // shadow edges and in the glass ball: shadow cubes of the refined radiosity meshes.)
  const Scene scene = load_scene(scene_path).scene;
  const BakeResult bake = bake_scene(scene, BakeParams{});
  RenderSettings settings;
  settings.tone.exposure = -2.5f;
  Image radiance, direct;
  {
    OffscreenContext context;
    Renderer renderer;
    renderer.set_scene(scene, nullptr);
    const ViewCamera camera = choose_camera(scene, "");
    renderer.render(camera, 320, 240, settings);
    direct = renderer.read_radiance();
    renderer.update_scene(scene, &bake);
    renderer.render(camera, 320, 240, settings);
    radiance = renderer.read_radiance();
  }
  auto to_srgb8 = [&](const Image& linear) {
    const std::vector<uint8_t> bytes = tonemap_to_srgb8(linear, settings.tone);
    Image image(linear.width, linear.height, 3);
    for (size_t i = 0; i < bytes.size(); ++i) image.pixels[i] = float(bytes[i]) / 255.0f;
    return image;
  };
  const Image offscreen = to_srgb8(radiance);

  ASSERT_EQ(window.width, offscreen.width);
  ASSERT_EQ(window.height, offscreen.height);
  ASSERT_EQ(window.channels, 3);
  const ImageDifference diff = compare_images(window, offscreen, 1.5f / 255.0f);
  if (diff.fraction_over > 0.0) test::write_comparison_files("window_bake_room", window, offscreen);
  EXPECT_EQ(diff.fraction_over, 0.0) << "largest difference " << diff.max_abs * 255.0 << "/255 at "
                                     << diff.max_x << "," << diff.max_y;

  // Not vacuous: the unbaked view differs (the radiosity brightens the room).
  EXPECT_GT(compare_images(window, to_srgb8(direct), 1.5f / 255.0f).fraction_over, 0.5);
}

}  // namespace
}  // namespace lb
