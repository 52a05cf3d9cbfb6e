// The GLFW window under Xvfb: it opens, renders the scene, saves a screenshot of the frame
// (read back from the window's back buffer, tone mapped on the GPU) and closes with status 0.
// The screenshot must equal the OSMesa snapshot of the same view tone mapped on the CPU:
// every channel of every pixel within 1/255 (GPU vs CPU rounding of the same formula).

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "bake/io/image_io.h"
#include "bake/io/scene_load.h"
#include "test_helpers.h"
#include "viewer/snapshot.h"
#include "viewer_test_scenes.h"

namespace lb {
namespace {

TEST(ViewerWindow, ScreenshotUnderXvfbEqualsOffscreenSnapshot) {
  if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "xvfb-run is not installed (Debian package xvfb)";
  const std::string scene_path = test::source_dir() + "/scenes/room.toml";
  const std::string screenshot = test::output_dir() + "/window_room.png";
  std::filesystem::remove(screenshot);
  const std::string command = test::xvfb_lightbake_command(
      "view " + scene_path + " --no-bake --size 320x240 --exposure -2.5 " +
      "--hide-panel --frames 3 --screenshot " + screenshot + " > /dev/null");
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  ASSERT_TRUE(std::filesystem::exists(screenshot));
  const Image window = read_image(screenshot, ImageDecode::as_stored);

  SnapshotOptions options;
  options.width = 320;
  options.height = 240;
  options.settings.tone.exposure = -2.5f;
  const Image radiance = render_snapshot(load_scene(scene_path).scene, nullptr, options);
  const std::vector<uint8_t> bytes = tonemap_to_srgb8(radiance, options.settings.tone);
  Image offscreen(radiance.width, radiance.height, 3);
  for (size_t i = 0; i < bytes.size(); ++i) offscreen.pixels[i] = float(bytes[i]) / 255.0f;

  ASSERT_EQ(window.width, offscreen.width);
  ASSERT_EQ(window.height, offscreen.height);
  ASSERT_EQ(window.channels, 3);
  const ImageDifference diff = compare_images(window, offscreen, 1.5f / 255.0f);
  if (diff.fraction_over > 0.0) test::write_comparison_files("window_room", window, offscreen);
  EXPECT_EQ(diff.fraction_over, 0.0) << "largest difference " << diff.max_abs * 255.0 << "/255 at "
                                     << diff.max_x << "," << diff.max_y;
}

}  // namespace
}  // namespace lb
