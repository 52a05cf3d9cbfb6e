// Per-chunk light lists (viewer/light_lists.h): each chunk keeps exactly the lights a hand
// count says can reach it, full-mode images are the same bits with lists on and off, and the
// stochastic running mean over the shorter lists converges to the full image.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>

#include "bake/io/scene_load.h"
#include "test_helpers.h"
#include "viewer/offscreen_context.h"
#include "viewer/renderer.h"
#include "viewer/snapshot.h"

namespace lb {
namespace {

constexpr int kWidth = 160, kHeight = 120;

// A diffuse material: `emission` W/(sr m^2) (a panel when not zero).
int add_diffuse(Scene& scene, float reflectance, float emission) {
  Material material;
  material.reflectance = vec3(reflectance);
  material.emission = vec3(emission);
  return test::add_material(scene, material);
}

// Rooms in a row along x, 5 m apart: closed boxes 4 x 3 x 4 m (inward), each with a 1 m
// panel hanging 0.5 m below the ceiling, facing down, and a block. (A panel 2 cm below the
// ceiling sees the ceiling at a grazing angle, where the shadow pass's slope-scaled polygon
// offset pushes its depth past the next room: the cubes then see over the wall, and the
// lists rightly keep those lights.) `open` joins rooms 0 and 1 into one box
// (x -2..7) holding both panels; the last room stays closed.
Scene rooms(int count, bool open) {
  Scene scene;
  scene.source_path = "rooms (in code)";
  const int grey = add_diffuse(scene, 0.6f, 0.0f);
  const int panel = add_diffuse(scene, 0.0f, 10.0f);
  for (int r = 0; r < count; ++r) {
    const float x = 5.0f * float(r);
    if (!(open && r == 1)) {
      const float x1 = open && r == 0 ? 7.0f : x + 2.0f;
      scene.meshes.push_back(test::make_box({x - 2, 0, -2}, {x1, 3, 2}, grey, true, "room"));
    }
    scene.meshes.push_back(
        test::make_quad({x - 0.5f, 2.5f, -0.5f}, {1, 0, 0}, {0, 0, 1}, panel, "panel"));
    scene.meshes.push_back(
        test::make_box({x + 0.3f, 0, -0.8f}, {x + 1.0f, 1.0f, -0.1f}, grey, false, "block"));
  }
  return scene;
}

// The lights of mesh m's only chunk, as read back from the list texture's ranges.
int list_length(const Renderer& renderer, size_t m, bool shadows) {
  const auto& ranges = renderer.light_lists().ranges(m, shadows);
  EXPECT_EQ(ranges.size(), 1u);
  return ranges.empty() ? -1 : ranges[0].y;
}

Image render(Renderer& renderer, const ViewCamera& camera, bool lists,
             const RenderSettings& settings) {
  Renderer::Culling culling;
  culling.light_lists = lists;
  renderer.set_culling(culling);
  renderer.render_flat(camera, kWidth, kHeight);  // a stochastic frame is then the first again
  renderer.render(camera, kWidth, kHeight, settings);
  return renderer.read_radiance();
}

bool same_bits(const Image& a, const Image& b) {
  return a.pixels.size() == b.pixels.size() &&
         std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(float)) == 0;
}

ViewCamera room_camera(float x) {
  ViewCamera camera;
  camera.position = {x - 1.5f, 1.6f, 1.5f};
  camera.target = {x + 1.5f, 0.6f, -1.0f};
  camera.vertical_fov_deg = 70.0f;
  return camera;
}

// Three closed rooms: each room's box and block keep their own light only (1 each); the
// walls hide the others' from every shadow cube. The panels keep all 3: they lie in one
// plane, so every other panel's corners sit on their horizon and its shadow points 1e-4 of
// the scene below it, inside the side tests' margin, and neither the "term zero" nor the
// "shadow point above" case is provable. Mean (6 x 1 + 3 x 3) / 9 = 5/3, max 3. Without
// shadows only the emitting side counts: nothing lies wholly above the panels (the room
// boxes reach the ceiling at 3 m, the panels hang at 2.5 m), so every chunk keeps all 3.
TEST(ViewerLightLists, ClosedRoomsKeepTheirOwnLight) {
  OffscreenContext context;
  const Scene scene = rooms(3, false);
  Renderer renderer;
  renderer.set_scene(scene);
  ASSERT_EQ(renderer.scene().meshes().size(), 9u);
  for (size_t m = 0; m < 9; ++m) {
    const bool panel = m % 3 == 1;
    EXPECT_EQ(list_length(renderer, m, true), panel ? 3 : 1) << "mesh " << m;
    EXPECT_EQ(list_length(renderer, m, false), 3) << "mesh " << m;
    if (panel) continue;
    // Which light: the room's own (lights are numbered in mesh order, one panel a room).
    const glm::ivec2 range = renderer.light_lists().ranges(m, true)[0];
    EXPECT_EQ(renderer.light_lists().light_at(range.x), int(m / 3)) << "mesh " << m;
  }
  EXPECT_DOUBLE_EQ(renderer.stats().lights_per_chunk_mean, 5.0 / 3.0);
  EXPECT_EQ(renderer.stats().lights_per_chunk_max, 3);
  std::printf("light list queries: %d\n", renderer.stats().light_list_queries);
}

// update_scene keeps the lists for the same geometry (new light colours) and falls back to
// every light (exact, only slower) when the meshes changed (a block moved 1 cm).
TEST(ViewerLightLists, UpdateSceneKeepsListsOnlyForTheSameGeometry) {
  OffscreenContext context;
  Scene scene = rooms(3, false);
  Renderer renderer;
  renderer.set_scene(scene);
  for (Material& material : scene.materials) {
    if (material.is_emitter()) material.emission = vec3(20.0f);
  }
  renderer.update_scene(scene, nullptr);
  EXPECT_EQ(list_length(renderer, 0, true), 1);
  EXPECT_EQ(list_length(renderer, 2, true), 1);
  for (vec3& p : scene.meshes[2].positions) p.x += 0.01f;
  renderer.update_scene(scene, nullptr);
  EXPECT_EQ(list_length(renderer, 0, true), 3);
  EXPECT_EQ(list_length(renderer, 2, true), 3);
}

// Full mode: lists on and off give the same bits, with shadows and without, in each room of
// the closed rooms and of the open pair (where room 0's chunks keep lights 0 and 1).
TEST(ViewerLightLists, FullModeSameBitsOnAndOff) {
  OffscreenContext context;
  for (const bool open : {false, true}) {
    const Scene scene = rooms(3, open);
    Renderer renderer;
    renderer.set_scene(scene);
    if (open) {
      EXPECT_EQ(list_length(renderer, 0, true), 2);  // the joined box
    }
    for (const bool shadows : {true, false}) {
      RenderSettings settings;
      settings.shadows = shadows;
      for (int r = 0; r < 3; ++r) {
        const ViewCamera camera = room_camera(5.0f * float(r));
        const Image on = render(renderer, camera, true, settings);
        const Image off = render(renderer, camera, false, settings);
        EXPECT_TRUE(same_bits(on, off))
            << "open " << open << " shadows " << shadows << " room " << r;
        double sum = 0.0;
        for (float v : on.pixels) sum += v;
        EXPECT_GT(sum, 0.0);
      }
    }
  }
}

// Mean |a - b| over mean b, all channels.
double relative_l1(const Image& a, const Image& b) {
  double diff = 0.0, total = 0.0;
  for (size_t i = 0; i < a.pixels.size(); ++i) {
    diff += std::abs(double(a.pixels[i]) - double(b.pixels[i]));
    total += std::abs(double(b.pixels[i]));
  }
  return diff / total;
}

// Stochastic mode in the open pair (lists {0, 1}; light 2, shut in its own room, dropped):
// the running mean of 64 still frames converges to the full image, and with less noise than
// when light 2 is still picked (and found shadowed). Relative L1 to the full image, measured:
// 1 frame 0.0286 with lists, 0.0409 without; 64 frames 0.00264 with, 0.00498 without.
// Tolerance 0.004 at 64 frames (what every light does not reach).
TEST(ViewerLightLists, StochasticMeanConvergesToFullImage) {
  OffscreenContext context;
  const Scene scene = rooms(3, true);
  Renderer renderer;
  renderer.set_scene(scene);
  const ViewCamera camera = room_camera(0.0f);
  const Image full = render(renderer, camera, true, RenderSettings{});
  RenderSettings stochastic;
  stochastic.direct_mode = DirectMode::stochastic;
  stochastic.refine_bands = 0;
  double error[2] = {0.0, 0.0};
  double error_one[2] = {0.0, 0.0};
  for (const bool lists : {true, false}) {
    Image mean = render(renderer, camera, lists, stochastic);
    error_one[lists] = relative_l1(mean, full);
    for (int f = 1; f < 64; ++f) renderer.render(camera, kWidth, kHeight, stochastic);
    EXPECT_EQ(renderer.accumulated_frames(), 64);
    mean = renderer.read_radiance();
    error[lists] = relative_l1(mean, full);
  }
  std::printf(
      "relative L1 to the full image: 1 frame %.5f lists, %.5f all lights; 64 frames "
      "%.5f lists, %.5f all lights\n",
      error_one[1], error_one[0], error[1], error[0]);
  EXPECT_LT(error[1], 0.004);
  EXPECT_LT(error[1], error_one[1] / 5.0);  // it converges, not merely starts close
  EXPECT_LT(error[1], error[0]);
  EXPECT_LT(error_one[1], error_one[0]);
}

// The bundled scenes, plain: full mode the same bits with lists on and off from their first
// camera; stochastic too where no chunk drops a light.
TEST(ViewerLightLists, BundledScenesSameBits) {
  OffscreenContext context;
  for (const auto& entry : std::filesystem::directory_iterator(test::source_dir() + "/scenes")) {
    if (entry.path().extension() != ".toml") continue;
    const Scene scene = load_scene(entry.path().string()).scene;
    Renderer renderer;
    renderer.set_scene(scene);
    const ViewCamera camera = choose_camera(scene, "");
    const int lights = int(renderer.scene().lights().lights.size());
    const bool drops = renderer.stats().lights_per_chunk_mean < double(lights);
    std::printf("%s: %d lights, %.2f a chunk (max %d)\n", entry.path().filename().c_str(), lights,
                renderer.stats().lights_per_chunk_mean, renderer.stats().lights_per_chunk_max);
    EXPECT_TRUE(same_bits(render(renderer, camera, true, RenderSettings{}),
                          render(renderer, camera, false, RenderSettings{})))
        << entry.path();
    if (drops) continue;
    RenderSettings stochastic;
    stochastic.direct_mode = DirectMode::stochastic;
    stochastic.refine_bands = 0;
    EXPECT_TRUE(same_bits(render(renderer, camera, true, stochastic),
                          render(renderer, camera, false, stochastic)))
        << entry.path();
  }
}

}  // namespace
}  // namespace lb
