// glTF alphaMode in the viewer (viewer/alpha_cut.h, shaders/alpha.glsl), against what the ray
// tracer does with the same scene (docs/gltf.md, "Alpha"): a leaf card cut by a 0/1 alpha
// checker (MASK: half its area, exactly, bilinearly read) and a pane of alpha 0.3 (BLEND:
// kept with probability 0.3 per pixel and per shadow-map texel), under a sun tilted so that
// their shadows fall clear of them in the camera's view. Before: both drawn solid, their
// shadows whole.

#include <gtest/gtest.h>

#include "test_helpers.h"
#include "viewer/snapshot.h"

namespace lb {
namespace {

constexpr int kWidth = 240, kHeight = 180;

// test::make_masked_leaf_scene's leaf (x, z in [-0.5, 0.5] at y = 0.5) and a pane of the
// same size beside it, the sun 56 degrees from straight down towards +x (their shadows 0.75 m
// along +x), seen from above on the +x side.
Scene leaf_and_pane(bool cut) {
  Scene scene = test::make_masked_leaf_scene(3.0f);
  Material pane = scene.materials[size_t(scene.meshes[1].material)];
  pane.name = "pane", pane.reflectance = vec3(0.8f);
  pane.alpha_mask = false, pane.alpha_blend = cut;
  pane.alpha_texture = -1, pane.alpha_factor = 0.3f;
  scene.materials.push_back(pane);
  scene.meshes.push_back(test::make_quad({-0.5f, 0.5f, -1.0f}, {1, 0, 0}, {0, 0, -1},
                                         int(scene.materials.size() - 1), "pane"));
  if (!cut) scene.materials[size_t(scene.meshes[1].material)].alpha_mask = false;
  scene.lights[0].direction = glm::normalize(vec3(1.5f, -1.0f, 0.0f));
  Camera camera;
  camera.position = {2.5f, 3.0f, -0.75f};
  camera.target = {0.4f, 0.0f, -0.75f};
  camera.vertical_fov_deg = 70.0f;
  scene.cameras.push_back(camera);
  return scene;
}

Image snapshot(const Scene& scene, Term term) {
  SnapshotOptions options;
  options.width = kWidth, options.height = kHeight;
  options.settings.term = term;
  return render_snapshot(scene, nullptr, options);
}

// Pixels whose reflectance is `r` (the leaf's 0.3, the pane's 0.8, the floor's 0.5).
int pixels_of(const Image& reflectance, float r) {
  int n = 0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) n += std::abs(reflectance.at(x, y, 0) - r) < 1e-3f;
  return n;
}

TEST(ViewerAlpha, MaskedLeafShowsHalfItselfAndBlendedPaneAlphaOfItself) {
  const Image cut = snapshot(leaf_and_pane(true), Term::reflectance);
  const Image solid = snapshot(leaf_and_pane(false), Term::reflectance);
  const double leaf = double(pixels_of(cut, 0.3f)) / pixels_of(solid, 0.3f);
  const double pane = double(pixels_of(cut, 0.8f)) / pixels_of(solid, 0.8f);
  std::printf("pixels kept: leaf %.4f (of %d), pane %.4f (of %d)\n", leaf,
              pixels_of(solid, 0.3f), pane, pixels_of(solid, 0.8f));
  EXPECT_GT(pixels_of(solid, 0.3f), 800);
  EXPECT_NEAR(leaf, 0.5, 0.03);  // the cut is exact in area; pixels sample it
  EXPECT_NEAR(pane, 0.3, 0.03);  // a coin per pixel: sd 0.015 over 1001 pixels
}

// The light the floor loses to each card's shadow (the direct term summed over the floor
// pixels that no card covers in any of the three frames), cut against solid: the leaf's shadow
// lets half the sun through, the pane's 0.7 (1 - alpha), as the ray tracer's shadow rays do.
TEST(ViewerAlpha, MaskedAndBlendedCardsCastTheirShareOfShadow) {
  Scene bare = leaf_and_pane(false);
  bare.meshes.resize(1);  // the floor alone
  const Image open = snapshot(bare, Term::direct);
  const Image cut = snapshot(leaf_and_pane(true), Term::direct);
  const Image solid = snapshot(leaf_and_pane(false), Term::direct);
  const Image cut_r = snapshot(leaf_and_pane(true), Term::reflectance);
  const Image solid_r = snapshot(leaf_and_pane(false), Term::reflectance);
  double lost_cut[2] = {0, 0}, lost_solid[2] = {0, 0};
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      if (std::abs(solid_r.at(x, y, 0) - 0.5f) > 1e-3f) continue;  // a card, or the sky
      if (std::abs(cut_r.at(x, y, 0) - 0.5f) > 1e-3f) continue;
      // Which card's shadow: the leaf's (z in [-0.5, 0.5]) is on the image's left, the
      // pane's (z in [-2, -1]) on its right.
      const int card = x < kWidth / 2 ? 0 : 1;
      lost_cut[card] += open.at(x, y, 0) - cut.at(x, y, 0);
      lost_solid[card] += open.at(x, y, 0) - solid.at(x, y, 0);
    }
  const double leaf = lost_cut[0] / lost_solid[0], pane = lost_cut[1] / lost_solid[1];
  std::printf("shadow cast, cut over solid: leaf %.4f, pane %.4f\n", leaf, pane);
  EXPECT_GT(lost_solid[0], 0.0);
  EXPECT_GT(lost_solid[1], 0.0);
  EXPECT_NEAR(leaf, 0.5, 0.05);
  EXPECT_NEAR(pane, 0.3, 0.05);
}

}  // namespace
}  // namespace lb
