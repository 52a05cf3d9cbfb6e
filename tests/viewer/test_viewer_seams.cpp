// The viewer draws a native bake's maps with their seams stitched, as the export stitches its
// map (viewer/gpu_scene.cpp, bake/lightmap/seam_stitch.h): four floor tiles, separate objects,
// at 10 texels/m under a small panel over their common corner (tests/data/web/seam_tiles.toml,
// the three.js check's scene). The seam between two tiles at x = 0 falls between the frame's
// columns 127 and 128 (its camera looks down at the origin); the baked terms' step there is
// measured against the floor's own step between neighbouring columns beside it, as
// tests/web/seam_jump.cpp measures three.js's frame, but on the linear radiance.

#include <gtest/gtest.h>

#include <cmath>

#include "bake/io/scene_load.h"
#include "bake/pipeline/bake.h"
#include "bake/pipeline/bake_settings.h"
#include "test_helpers.h"
#include "viewer/snapshot.h"

namespace lb {
namespace {

constexpr int kWidth = 256, kHeight = 192, kSeamColumn = 128;

// Mean |L(x) - L(x - 1)| over the tiles' rows (the panel's rows left out) of channel 0.
double step_at(const Image& image, int x) {
  double sum = 0.0;
  int rows = 0;
  for (auto [first, last] : {std::pair{30, 91}, std::pair{112, 164}})
    for (int y = first; y <= last; ++y, ++rows)
      sum += std::abs(double(image.at(x, y)) - double(image.at(x - 1, y)));
  return sum / rows;
}

TEST(ViewerSeams, ANativeBakesSeamStepsLikeTheFloorBesideIt) {
  const Scene scene = load_scene(test::source_dir() + "/tests/data/web/seam_tiles.toml").scene;
  const BakeResult bake = bake_scene(scene, resolve_bake_params(scene, {}));
  SnapshotOptions options;
  options.width = kWidth, options.height = kHeight;
  options.settings.term = Term::baked;
  const Image image = render_snapshot(scene, &bake, options);
  double interior = 0.0;
  for (int d = 3; d <= 8; ++d) interior += step_at(image, kSeamColumn - d + 1);
  for (int d = 1; d <= 6; ++d) interior += step_at(image, kSeamColumn + d + 1);
  interior /= 12.0;
  const double seam = step_at(image, kSeamColumn);
  std::printf("seam step %.3g, the floor's %.3g W/(sr m^2): ratio %.2f\n", seam, interior,
              seam / interior);
  // Measured 1.30 (drawn unstitched, as before: 25.0).
  EXPECT_GT(interior, 0.0);
  EXPECT_LT(seam / interior, 2.0);
}

}  // namespace
}  // namespace lb
