// HQ mode in the window (viewer/hq_view.h).
// - Under Xvfb: `view --hq` refines the baked Cornell box for 3 passes of 4 spp, dumps the film
//   and a screenshot, switches back to raster for 3 frames and exits 0. The film has the bits
//   of `lightbake render` at the same size, seed, spp and passes over the same bake (every
//   value; 0 differ), and the screenshot is `render`'s PNG within 1/255 (the same formula,
//   tonemap.frag on the GPU vs image_io on the CPU, as in test_viewer_window).
//   The same after a bake made in the window (no BAKE_DIR) against `render` baking itself.
// - Offscreen: a view change while a pass runs cancels it (measured latency printed), nothing
//   of the old view is ever shown, and the film of the new view has the bits of HqRenderer's
//   own passes. hq_camera keeps the scene camera while the view equals it.

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <thread>

#include "bake/camera.h"
#include "bake/io/image_io.h"
#include "bake/io/scene_load.h"
#include "bake/pipeline/bake.h"
#include "test_helpers.h"
#include "viewer/hq_view.h"
#include "viewer/offscreen_context.h"

namespace lb {
namespace {

namespace fs = std::filesystem;

TEST(ViewerWindowHq, FilmAfterThreePassesEqualsRenderBitForBitThenRasterAndCleanExit) {
  if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "xvfb-run is not installed (Debian package xvfb)";
  const fs::path dir = test::fresh_dir("viewer_hq", "window");
  const std::string scene = test::source_dir() + "/scenes/cornell_box.toml";
  const std::string bake = (dir / "bake").string();
  const test::CliRun baked = test::run_lightbake("bake '" + scene + "' -q -o '" + bake + "'");
  ASSERT_EQ(baked.status, 0) << baked.err;
  const std::string settings = " --size 96x72 --spp 4 --passes 3 --seed 7";
  for (const char* ext : {"exr", "png"}) {
    const test::CliRun render =
        test::run_lightbake("render '" + scene + "' '" + bake + "'" + settings + " -q -o '" +
                            (dir / "render.").string() + ext + "'");
    ASSERT_EQ(render.status, 0) << render.err;
  }

  const std::string out = (dir / "view.out").string(), err = (dir / "view.err").string();
  const std::string command = test::xvfb_lightbake_command(
      "view '" + scene + "' '" + bake + "'" + settings +
      " --hq --frames 3 --hide-panel --hq-exr '" + (dir / "window.exr").string() +
      "' --screenshot '" + (dir / "window.png").string() + "' > '" + out + "' 2> '" + err + "'");
  const int status = std::system(command.c_str());
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << command << "\n"
                                                             << test::read_bytes(err);
  const std::string log = test::read_bytes(out);
  std::printf("%s", log.c_str());
  EXPECT_NE(log.find("hq: 3 passes, 12 samples per pixel, 96x72"), std::string::npos) << log;
  EXPECT_NE(log.find("raster: 3 frames after HQ"), std::string::npos) << log;

  const Image window = read_image((dir / "window.exr").string());
  const Image render = read_image((dir / "render.exr").string());
  ASSERT_EQ(window.width, 96);
  ASSERT_EQ(window.height, 72);
  ASSERT_EQ(render.width, 96);
  ASSERT_EQ(render.channels, window.channels);
  size_t differing = 0;
  for (size_t i = 0; i < window.pixels.size(); ++i)
    differing += std::memcmp(&window.pixels[i], &render.pixels[i], sizeof(float)) != 0;
  EXPECT_EQ(differing, 0u) << "of " << window.pixels.size() << " values";
  double sum = 0.0;  // not a black image: the box's mean radiance is about 0.11 W/(sr m^2)
  for (float v : window.pixels) sum += v;
  EXPECT_GT(sum / double(window.pixels.size()), 0.01);

  const Image shot = read_image((dir / "window.png").string(), ImageDecode::as_stored);
  const Image png = read_image((dir / "render.png").string(), ImageDecode::as_stored);
  ASSERT_EQ(shot.width, png.width);
  ASSERT_EQ(shot.height, png.height);
  const ImageDifference diff = compare_images(shot, png, 1.5f / 255.0f);
  std::printf("screenshot vs render PNG: largest difference %.0f/255\n", diff.max_abs * 255.0);
  EXPECT_EQ(diff.fraction_over, 0.0) << "largest " << diff.max_abs * 255.0 << "/255";
}

// Without BAKE_DIR both bake first with the same params (seed, the scene's quality): HQ starts
// on the window's own bake once it ends, and still has render's bits.
TEST(ViewerWindowHq, AfterABakeInTheWindowFilmEqualsRenderThatBakesItself) {
  if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "xvfb-run is not installed (Debian package xvfb)";
  const fs::path dir = test::fresh_dir("viewer_hq", "window_bake");
  const std::string scene = test::source_dir() + "/scenes/cornell_box.toml";
  const std::string settings = " --size 64x48 --spp 4 --passes 2";
  const test::CliRun render = test::run_lightbake("render '" + scene + "'" + settings + " -q -o '" +
                                                  (dir / "render.exr").string() + "'");
  ASSERT_EQ(render.status, 0) << render.err;
  const std::string out = (dir / "view.out").string();
  const std::string command = test::xvfb_lightbake_command(
      "view '" + scene + "'" + settings + " --hq --frames 2 --hq-exr '" +
      (dir / "window.exr").string() + "' > '" + out + "'");
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  const std::string log = test::read_bytes(out);
  EXPECT_NE(log.find("baked: "), std::string::npos) << log;
  EXPECT_NE(log.find("hq: 2 passes, 8 samples per pixel, 64x48"), std::string::npos) << log;
  const Image window = read_image((dir / "window.exr").string());
  const Image expected = read_image((dir / "render.exr").string());
  ASSERT_EQ(window.pixels.size(), size_t(64 * 48 * 3));
  EXPECT_TRUE(test::same_bits(window.pixels, expected.pixels));
}

TEST(ViewerWindowHq, ViewChangeCancelsRunningPassAndNewFilmEqualsRendererPasses) {
  const Scene scene = load_scene(test::source_dir() + "/scenes/cornell_box.toml").scene;
  BakeParams bake_params;
  apply_quality(scene, Quality::draft, bake_params);
  const BakeResult bake = bake_scene(scene, bake_params);
  const Camera first = select_camera(scene, "");

  // The view still at the scene camera renders with it; moved, a pinhole at the view.
  ViewCamera view = ViewCamera::from(first);
  EXPECT_EQ(hq_camera(view, scene, first).name, first.name);
  view.position.x += 0.01f;
  const Camera moved = hq_camera(view, scene, first);
  EXPECT_EQ(moved.name, "view");
  EXPECT_EQ(moved.position, view.position);

  OffscreenContext context;
  HqView hq("");
  HqParams params;
  params.samples_per_side = 12;  // 144 spp at 160x120: a pass of about half a second
  hq.set_params(params, 2);
  hq.set_bake(scene, &bake);
  auto wait = [&](auto done) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(50);
    while (!done() && std::chrono::steady_clock::now() < end)
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    return done();
  };
  hq.update(first, 160, 120, true);
  ASSERT_TRUE(wait([&] { return hq.fraction() > 0.05; })) << hq.stage() << hq.error();
  ASSERT_FALSE(hq.ready());  // the first pass is still under way
  const auto cancel_start = std::chrono::steady_clock::now();
  hq.update(moved, 160, 120, false);  // the camera moves: cancel, do not start
  EXPECT_FALSE(hq.ready());
  ASSERT_TRUE(wait([&] { return !hq.running(); }));
  const double cancel_ms =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - cancel_start).count() * 1e3;
  std::printf("running pass cancelled in %.1f ms\n", cancel_ms);
  EXPECT_FALSE(hq.ready());          // the cancelled pass left nothing
  hq.update(moved, 160, 120, true);  // at rest: two passes of the new view
  ASSERT_TRUE(wait([&] { return !hq.running() && hq.ready(); })) << hq.error();
  hq.present(ToneMap{}, 160, 120);
  ASSERT_EQ(hq.shown_passes(), 2);
  EXPECT_EQ(hq.shown_samples_per_pixel(), 288u);
  // Cancelling took a small part of what the pass it stopped would have taken.
  std::printf("a whole pass: %.1f ms\n", hq.last_pass_seconds() * 1e3);
  EXPECT_LT(cancel_ms, 0.5 * hq.last_pass_seconds() * 1e3);

  params.width = 160;
  params.height = 120;
  const BakedScene baked = make_baked_scene(scene, bake);
  const HqRenderer renderer(baked, params);
  HqStats stats;
  const std::vector<vec3> expected = renderer.render(moved, 2, stats);
  EXPECT_TRUE(test::same_bits(hq.shown_pixels(), expected));
}

}  // namespace
}  // namespace lb
