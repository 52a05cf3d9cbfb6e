// Round trip of every bundled scene through the glTF export: bake, `lightbake export`, then
// `snapshot out.glb` (the light read back from the file, no new bake) against `snapshot
// SCENE BAKE_DIR` (the bake itself), same camera, linear radiance (EXR). Once with the
// half-float EXR beside the file, once with the glTF alone (the 8-bit lightmap PNG inside).
// What may differ: the soft light, which the bake's snapshot interpolates between the refined
// radiosity mesh's vertices and the file holds resampled into lightmap texels (bilinear between
// texel centres: the two differ where the soft light bends, at contacts and shadow edges);
// half-float and 8-bit rounding of the map; and on fig6_bump the height-map bump, which the
// file holds as the normal map that shades the same (docs/export.md, Materials).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "bake/io/image_io.h"
#include "bake/metrics/image_metrics.h"
#include "test_helpers.h"

namespace lb {
namespace {

namespace fs = std::filesystem;

const char* const kScenes[] = {
    "cornell_box",      "cornell_glass",    "fig3_ring",      "fig4_plates",
    "fig5_nine_lights", "fig6_bump",        "fig7_glass",     "lamps",
    "room",             "room_no_ball",     "room_small_light", "room_two_blocks",
    "studded_wall"};

TEST(GltfRoundTrip, CoversEveryBundledScene) {
  std::set<std::string> bundled, tested(std::begin(kScenes), std::end(kScenes));
  for (const auto& entry : fs::directory_iterator(test::source_dir() + "/scenes"))
    if (entry.path().extension() == ".toml") bundled.insert(entry.path().stem().string());
  EXPECT_EQ(bundled, tested);
}

ImageMetrics compare_exr(const fs::path& image, const fs::path& reference) {
  return compare_to_reference(read_image(image.string()), read_image(reference.string()));
}

class GltfRoundTrip : public testing::TestWithParam<const char*> {};

TEST_P(GltfRoundTrip, SnapshotOfTheExportEqualsSnapshotOfTheBake) {
  const std::string name = GetParam();
  std::string scene = "'";  // appended: GCC 12's -Wrestrict misfires on "'" + std::string
  scene.append(test::source_dir()).append("/scenes/").append(name).append(".toml'");
  const fs::path dir = test::fresh_dir("gltf_roundtrip", name);
  const std::string size = " --size 160x120 ";
  ASSERT_EQ(test::run_lightbake("bake -q " + scene + " -o bake", dir.string()).status, 0);
  ASSERT_EQ(test::run_lightbake("export -q " + scene + " bake -o out.glb", dir.string()).status, 0);
  ASSERT_EQ(
      test::run_lightbake("snapshot -q " + scene + " bake" + size + "-o orig.exr", dir.string())
          .status,
      0);
  const test::CliRun back =
      test::run_lightbake("snapshot -q out.glb" + size + "-o back.exr", dir.string());
  ASSERT_EQ(back.status, 0) << back.err;
  EXPECT_EQ(back.err.find("baking"), std::string::npos) << "the file's light, not a new bake";

  const ImageMetrics exr = compare_exr(dir / "back.exr", dir / "orig.exr");
  std::printf("%s: out.glb (+ EXR) vs the bake: MRE %.3g, sum ratio %.7f\n", name.c_str(),
              exr.mean_relative_error, exr.sum_ratio_total);
  RecordProperty("mre", std::to_string(exr.mean_relative_error));
  // Measured (2026-11-30, again after the atlas strips) at most MRE 7.2e-3 (cornell_glass),
  // sum ratio 0.99789 (room_two_blocks): the texel resampling of the soft light. Scenes lit
  // mostly by caustics and direct light agree to 2.1e-4 (fig3, fig4, fig5, fig7, lamps,
  // room_small_light); fig6_bump, its height bump written as a normal map, to 6.9e-4 (sum
  // ratio 0.99957; 1.24e-2 and 1.0062 when the export dropped the bump). The limits are 1.4x
  // those: too close to tighten to 2x.
  EXPECT_LT(exr.mean_relative_error, 1e-2);
  EXPECT_NEAR(exr.sum_ratio_total, 1.0, 3e-3);

  // The glTF alone: the map from the 8-bit sRGB PNG inside it.
  if (!fs::exists(dir / "out.lightmap.exr")) return;  // no lightmap to read
  fs::create_directories(dir / "alone");
  fs::copy_file(dir / "out.glb", dir / "alone" / "out.glb");
  ASSERT_EQ(
      test::run_lightbake("snapshot -q out.glb" + size + "-o back.exr", (dir / "alone").string())
          .status,
      0);
  const ImageMetrics png = compare_exr(dir / "alone" / "back.exr", dir / "orig.exr");
  std::printf("%s: out.glb alone (8-bit map) vs the bake: MRE %.3g, sum ratio %.7f\n", name.c_str(),
              png.mean_relative_error, png.sum_ratio_total);
  RecordProperty("mre_png", std::to_string(png.mean_relative_error));
  // 8-bit sRGB steps are at most 0.45% of the map's scale (docs/export.md), on top of the
  // resampling above. Measured at most MRE 1.21e-2 (cornell_glass), sum ratio 0.99789
  // (room_two_blocks), again after the atlas strips: the limits are 1.7x and 1.4x those.
  EXPECT_LT(png.mean_relative_error, 2e-2);
  EXPECT_NEAR(png.sum_ratio_total, 1.0, 3e-3);
}

// Directional maps (docs/export.md): on the Cornell box, whose surfaces have no normal map,
// `snapshot out.glb` (the band drawn wherever the file has one) draws the plain map (`snapshot
// --no-directional`; the L1 band is tangential: L1 . n0 = 0 but for the 8-bit ratios; 2% off
// on the short block when charts unfolded across its edges
// mixed two faces' L1, before the projection onto each node's tangent plane). On the studded
// wall (a normal map) the band changes the picture, and its mean by what the studs' tilted
// normals lose: the reference's frame sums 1/1.0406 of the plain map's (4096 spp at 256 x 192,
// bench/directional.py, 2026-12-07); with the share s in the file (`--directional-share`)
// within 0.5% of that (the decode's W term, export.md); without it (the default, W = 1/2) the
// tilted normals lose less of L0, so the frame lies between that and the plain map's.
TEST(GltfDirectional, FlatSurfacesDrawThePlainMapNormalMapsDoNot) {
  double sum_without_share = 0.0, sum_with_share = 0.0;
  for (const auto& [name, share] : {std::pair<std::string, bool>{"cornell_box", false},
                                    {"studded_wall", false},
                                    {"studded_wall", true}}) {
    std::string scene = "'";
    scene.append(test::source_dir()).append("/scenes/").append(name).append(".toml'");
    const fs::path dir = test::fresh_dir("gltf_directional", name + (share ? "_share" : ""));
    const std::string size = " --size 96x72 --terms baked ";
    ASSERT_EQ(test::run_lightbake("export -q " + scene + " -o out.glb --contents all "
                                  "--directional --direct-samples 2 --quality draft" +
                                      std::string(share ? " --directional-share" : ""),
                                  dir.string())
                  .status,
              0);
    ASSERT_EQ(test::run_lightbake("snapshot -q out.glb --no-directional" + size + "-o plain.exr",
                                  dir.string())
                  .status,
              0);
    ASSERT_EQ(test::run_lightbake("snapshot -q out.glb" + size + "-o band.exr", dir.string())
                  .status,
              0);
    const ImageMetrics m = compare_exr(dir / "band.exr", dir / "plain.exr");
    std::printf("%s%s: directional vs plain: MRE %.3g, sum ratio %.6f\n", name.c_str(),
                share ? " (share)" : "", m.mean_relative_error, m.sum_ratio_total);
    if (name == "cornell_box") {
      EXPECT_LT(m.mean_relative_error, 1e-3);
      EXPECT_NEAR(m.sum_ratio_total, 1.0, 2e-3);
    } else {
      EXPECT_GT(m.mean_relative_error, 0.05);
      (share ? sum_with_share : sum_without_share) = m.sum_ratio_total;
    }
  }
  EXPECT_NEAR(sum_with_share, 1.0 / 1.0406, 5e-3);
  EXPECT_GT(sum_without_share, sum_with_share + 5e-3);
  EXPECT_LT(sum_without_share, 1.0 - 5e-3);
}

// A bake's soft band (bake --directional; bake/lightmap/soft_band.h) drawn by `snapshot` of the
// bake: a studded wall (the studded_wall scene's normal map) beside a flat one, lit by a panel
// and a floor's bounce. The flat wall (the right half of the frame) keeps its pixels' bits,
// the studs change with --directional (the band) against --no-directional (the map flat).
TEST(BakeDirectional, SnapshotDrawsTheSoftBandOnNormalMapsOnly) {
  const fs::path dir = test::fresh_dir("bake_directional", "soft_band");
  const std::string textures = test::source_dir() + "/scenes/textures/studs_normal.png";
  std::ofstream(dir / "walls.toml") << R"([materials]
studs = { reflectance = [0.7, 0.68, 0.64], bump = { normal = ")" << textures << R"(", scale = 1 } }
plain = { reflectance = [0.7, 0.68, 0.64] }
floor = { reflectance = [0.5, 0.45, 0.4] }
panel = { reflectance = 0, power = 120 }

[[objects]]
name = "studs"
shape = "quad"
corner = [-1.0, 0.0, 0.0]
edge_u = [1.0, 0.0, 0.0]
edge_v = [0.0, 1.5, 0.0]
uv_tile = 0.1
material = "studs"

[[objects]]
name = "flat"
shape = "quad"
corner = [0.0, 0.0, 0.0]
edge_u = [1.0, 0.0, 0.0]
edge_v = [0.0, 1.5, 0.0]
material = "plain"

[[objects]]
name = "floor"
shape = "quad"
corner = [-2.6, 0.0, 1.5]
edge_u = [3.6, 0.0, 0.0]
edge_v = [0.0, 0.0, -1.5]
material = "floor"

[[objects]]
name = "panel"
shape = "quad"
size = [0.6, 0.6]
normal = [1.0, 0.0, -1.0]
translate = [-1.0, 0.75, 1.0]
material = "panel"

[[cameras]]
name = "front"
position = [0.0, 0.75, 1.6]
target = [0.0, 0.75, 0.0]
fov = 46
)";
  ASSERT_EQ(test::run_lightbake("bake -q walls.toml -o bake --directional --quality draft",
                                dir.string())
                .status,
            0);
  const std::string snapshot = "snapshot -q walls.toml bake --size 96x72 --terms baked ";
  ASSERT_EQ(test::run_lightbake(snapshot + "-o band.exr", dir.string()).status, 0);
  ASSERT_EQ(test::run_lightbake(snapshot + "--no-directional -o flat.exr", dir.string()).status,
            0);
  const Image band = read_image((dir / "band.exr").string());
  const Image flat = read_image((dir / "flat.exr").string());
  ASSERT_EQ(band.width, 96);
  ASSERT_EQ(flat.width, 96);
  double studs_change = 0.0, studs_light = 0.0;
  int flat_pixels = 0, flat_same = 0;
  for (int y = 0; y < band.height; ++y)
    for (int x = 0; x < band.width; ++x) {
      if (x >= 44 && x < 52) continue;  // the walls' seam
      for (int c = 0; c < 3; ++c) {
        const float a = band.at(x, y, c), b = flat.at(x, y, c);
        if (x < 44) {
          studs_change += std::abs(double(a) - double(b));
          studs_light += double(b);
        } else {
          ++flat_pixels;
          flat_same += a == b;
        }
      }
    }
  std::printf("bake's soft band in a snapshot: the studs change by %.4f of their light; flat "
              "wall: %d of %d values the same\n",
              studs_change / studs_light, flat_same, flat_pixels);
  EXPECT_GT(studs_change / studs_light, 0.02);
  EXPECT_EQ(flat_same, flat_pixels);
}

INSTANTIATE_TEST_SUITE_P(BundledScenes, GltfRoundTrip, testing::ValuesIn(kScenes),
                         [](const testing::TestParamInfo<const char*>& info) {
                           return std::string(info.param);
                         });

}  // namespace
}  // namespace lb
