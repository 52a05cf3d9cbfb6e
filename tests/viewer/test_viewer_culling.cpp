// Culling (viewer/frustum.h, viewer/mesh_chunks.h, Renderer::Culling): it drops only what a
// pass cannot see, so images are the same bits with it on and off, and it skips the chunks a
// hand count says lie outside the view; camera occlusion drops only what the depth hides.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <glm/gtc/matrix_transform.hpp>
#include <string>
#include <vector>

#include "test_helpers.h"
#include "viewer/frustum.h"
#include "viewer/mesh_chunks.h"
#include "viewer/occlusion_schedule.h"
#include "viewer/offscreen_context.h"
#include "viewer/renderer.h"

namespace lb {
namespace {

// Appends `part`'s triangles to `mesh` (positions and normals; both made by make_box).
void append(Mesh& mesh, const Mesh& part) {
  const uint32_t base = uint32_t(mesh.positions.size());
  mesh.positions.insert(mesh.positions.end(), part.positions.begin(), part.positions.end());
  mesh.normals.insert(mesh.normals.end(), part.normals.begin(), part.normals.end());
  for (const uvec3& t : part.triangles) mesh.triangles.push_back(t + uvec3(base));
}

int add_grey(Scene& scene, float reflectance) {
  Material grey;
  grey.reflectance = vec3(reflectance);
  return test::add_material(scene, grey);
}

int add_lamp(Scene& scene) {  // 10 W/(sr m^2) white
  Material lamp;
  lamp.reflectance = vec3(0.0f);
  lamp.emission = vec3(10.0f);
  return test::add_material(scene, lamp);
}

// `count` unit boxes (12 triangles each) in one mesh, box i centred at (2 i, 0, 0).
Mesh box_row(int count, int material) {
  Mesh row;
  row.name = "row";
  row.material = material;
  for (int i = 0; i < count; ++i) {
    append(row, test::make_box({2.0f * float(i) - 0.5f, -0.5f, -0.5f},
                               {2.0f * float(i) + 0.5f, 0.5f, 0.5f}, material, false));
  }
  return row;
}

TEST(MeshChunks, SmallMeshIsOneChunkInItsOwnOrder) {
  const Mesh mesh = box_row(10, 0);  // 120 triangles
  const MeshChunks chunks = make_mesh_chunks(mesh);
  ASSERT_EQ(chunks.chunks.size(), 1u);
  EXPECT_EQ(chunks.chunks[0].triangle_count, 120u);
  for (uint32_t k = 0; k < 120; ++k) EXPECT_EQ(chunks.order[k], k);
}

// 1024 boxes = 12288 triangles: two median splits along x make 4 chunks of 3072 (<= 4096), box
// 256 k to 256 k + 255 in chunk k, each triangle exactly once, each inside its chunk's box.
TEST(MeshChunks, SplitsAlongTheLongAxisIntoBoundedChunks) {
  const Mesh mesh = box_row(1024, 0);
  const MeshChunks chunks = make_mesh_chunks(mesh);
  ASSERT_EQ(chunks.chunks.size(), 4u);
  std::vector<uint32_t> sorted = chunks.order;
  std::sort(sorted.begin(), sorted.end());
  for (uint32_t t = 0; t < sorted.size(); ++t) ASSERT_EQ(sorted[t], t);
  for (size_t k = 0; k < 4; ++k) {
    const MeshChunk& c = chunks.chunks[k];
    EXPECT_EQ(c.first_triangle, 3072u * k);
    EXPECT_EQ(c.triangle_count, 3072u);
    EXPECT_FLOAT_EQ(c.bounds.min.x, 512.0f * float(k) - 0.5f);
    EXPECT_FLOAT_EQ(c.bounds.max.x, 512.0f * float(k) + 510.5f);
    for (uint32_t i = c.first_triangle; i < c.first_triangle + c.triangle_count; ++i) {
      EXPECT_EQ(chunks.order[i] / 12 / 256, k);  // box index / 256
      if (i > c.first_triangle) {
        EXPECT_LT(chunks.order[i - 1], chunks.order[i]);  // the mesh's own order
      }
    }
  }
}

TEST(Frustum, CullsOnlyBoxesWhollyOutside) {
  // 90 degrees, square: at depth d the view spans |x|, |y| <= d.
  const glm::mat4 clip = glm::perspective(glm::radians(90.0f), 1.0f, 0.1f, 100.0f) *
                         glm::lookAt(vec3(0.0f), vec3(0, 0, -1), vec3(0, 1, 0));
  const Frustum frustum(clip);
  auto box = [](vec3 lo, vec3 hi) {
    Bounds b;
    b.extend(lo);
    b.extend(hi);
    return b;
  };
  EXPECT_TRUE(frustum.may_see(box({-1, -1, -5}, {1, 1, -4})));
  EXPECT_TRUE(frustum.may_see(box({3.9f, 0, -4.5f}, {6, 1, -4})));   // corner x 3.9 < depth 4
  EXPECT_FALSE(frustum.may_see(box({4.6f, 0, -4.5f}, {6, 1, -4})));  // x 4.6 > depth 4.5
  EXPECT_FALSE(frustum.may_see(box({-1, -1, 1}, {1, 1, 2})));        // behind the eye
  EXPECT_FALSE(frustum.may_see(box({-1, -1, -102}, {1, 1, -101})));  // beyond the far plane
  EXPECT_TRUE(Frustum().may_see(box({-1, -1, 1}, {1, 1, 2})));       // no planes: everything
}

// cube_face_matrix is shaders/shadows.glsl's mapping: for face +y (2), clip = (d.z, d.x,
// a m + b, m) with m = d.y.
TEST(Frustum, CubeFaceMatrixIsTheShadersMapping) {
  const vec3 centre(1.0f, 2.0f, 3.0f), d(0.3f, 2.0f, -0.7f);
  const float near = 0.1f, far = 10.0f;
  const glm::vec4 clip = cube_face_matrix(centre, 2, near, far) * glm::vec4(centre + d, 1.0f);
  const float a = (far + near) / (far - near), b = -2.0f * far * near / (far - near);
  EXPECT_NEAR(clip.x, d.z, 1e-6f);
  EXPECT_NEAR(clip.y, d.x, 1e-6f);
  EXPECT_NEAR(clip.z, a * d.y + b, 1e-5f);
  EXPECT_NEAR(clip.w, d.y, 1e-6f);
  const Frustum up(cube_face_matrix(centre, 2, near, far));
  Bounds above, below;
  above.extend(centre + vec3(-0.5f, 1.0f, -0.5f));
  above.extend(centre + vec3(0.5f, 2.0f, 0.5f));
  below.extend(centre + vec3(-0.5f, -2.0f, -0.5f));
  below.extend(centre + vec3(0.5f, -1.0f, 0.5f));
  EXPECT_TRUE(up.may_see(above));
  EXPECT_FALSE(up.may_see(below));
}

constexpr int kWidth = 160, kHeight = 120;

// A 7 x 7 grid of 0.4 m boxes 1 m apart on a floor, in two meshes of 12 boxes each plus 25
// single boxes, 576 pebbles in one mesh of two chunks, a planar mirror on one side, a 1 m
// ceiling light at 3 m.
Scene box_grid() {
  Scene scene;
  scene.source_path = "box grid (in code)";
  const int grey = add_grey(scene, 0.6f);
  Material mirror;
  mirror.kind = MaterialKind::mirror;
  mirror.reflectance = vec3(0.9f);
  const int mirror_id = test::add_material(scene, mirror);
  scene.meshes.push_back(test::make_quad({-5, 0, -5}, {0, 0, 10}, {10, 0, 0}, grey, "floor"));
  scene.meshes.push_back(
      test::make_quad({-0.5f, 3, -0.5f}, {1, 0, 0}, {0, 0, 1}, add_lamp(scene), "light"));
  scene.meshes.push_back(
      test::make_quad({-4.5f, 0, -4.5f}, {9, 0, 0}, {0, 2, 0}, mirror_id, "mirror"));  // faces +z
  Mesh first, second;
  first.material = second.material = grey;
  for (int i = 0; i < 49; ++i) {
    const float x = float(i % 7) - 3.0f, z = float(i / 7) - 3.0f;
    Mesh box = test::make_box({x - 0.2f, 0, z - 0.2f}, {x + 0.2f, 0.4f, z + 0.2f}, grey, false);
    if (i < 12) {
      append(first, box);
    } else if (i < 24) {
      append(second, box);
    } else {
      scene.meshes.push_back(box);
    }
  }
  scene.meshes.push_back(first);
  scene.meshes.push_back(second);
  // 576 pebbles of 5 cm in one mesh: 6912 triangles, two chunks.
  Mesh pebbles;
  pebbles.material = grey;
  for (int i = 0; i < 576; ++i) {
    const float x = 0.38f * float(i % 24) - 4.4f, z = 0.38f * float(i / 24) - 4.3f;
    append(pebbles, test::make_box({x, 0, z}, {x + 0.05f, 0.05f, z + 0.05f}, grey, false));
  }
  scene.meshes.push_back(pebbles);
  return scene;
}

Image render(Renderer& renderer, const ViewCamera& camera, Renderer::Culling culling,
             const RenderSettings& settings = {}) {
  renderer.set_culling(culling);
  renderer.render_flat(camera, kWidth, kHeight);  // a stochastic frame is then the first again
  renderer.render(camera, kWidth, kHeight, settings);
  return renderer.read_radiance();
}

bool same_bits(const Image& a, const Image& b) {
  return a.pixels.size() == b.pixels.size() &&
         std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(float)) == 0;
}

double pixel_sum(const Image& image) {
  double sum = 0.0;
  for (float v : image.pixels) sum += v;
  return sum;
}

struct View {
  const char* name;
  vec3 position, target;
};

ViewCamera camera_for(const View& view, float vertical_fov_deg) {
  ViewCamera camera;
  camera.position = view.position;
  camera.target = view.target;
  camera.vertical_fov_deg = vertical_fov_deg;
  return camera;
}

// The moving camera's frames: stochastic, each the first of its view.
RenderSettings stochastic_settings() {
  RenderSettings stochastic;
  stochastic.direct_mode = DirectMode::stochastic;
  stochastic.refine_bands = 0;
  return stochastic;
}

// Same bits with culling off, frustum culling alone and with the depth pre-pass (and camera
// occlusion, on by default), from outside the grid, from inside it (most boxes behind or
// beside the eye), from above, looking into the mirror (its mirrored pass culls with its own
// frustum) and looking at nothing.
TEST(ViewerCulling, SameBitsOnAndOff) {
  OffscreenContext context;
  const Scene scene = box_grid();
  Renderer renderer;
  renderer.set_scene(scene);
  const View views[] = {{"outside", {5.0f, 1.5f, 5.0f}, {0.0f, 0.2f, 0.0f}},
                        {"inside", {0.5f, 0.25f, 0.5f}, {3.0f, 0.2f, -0.6f}},
                        {"above", {0.0f, 6.0f, 0.5f}, {0.0f, 0.0f, 0.0f}},
                        {"mirror", {1.0f, 1.0f, 3.5f}, {-0.5f, 0.8f, -4.5f}},
                        {"away", {0.0f, 1.0f, 4.8f}, {0.0f, 1.0f, 10.0f}}};
  for (const View& view : views) {
    const ViewCamera camera = camera_for(view, 60.0f);
    for (const RenderSettings& settings : {RenderSettings{}, stochastic_settings()}) {
      const Image off = render(renderer, camera, {false, false, false}, settings);
      const int total = renderer.stats().view.chunks_total;
      const Image frustum = render(renderer, camera, {true, false}, settings);
      const int drawn = renderer.stats().view.chunks_drawn;
      const Image both = render(renderer, camera, {true, true}, settings);
      EXPECT_TRUE(same_bits(off, frustum)) << view.name;
      EXPECT_TRUE(same_bits(off, both)) << view.name;
      if (std::string(view.name) != "away") {
        EXPECT_GT(pixel_sum(off), 0.0) << view.name;  // not a blank image
      }
      std::printf("%s: %d of %d chunks drawn\n", view.name, drawn, total);
    }
  }
}

// Ten unit boxes (separate meshes) centred at x = 0, 3, ..., 27, z = -4, and the 1024-box row
// of 4 chunks at z = -10; the camera at the origin looks down -z with a square 90-degree view,
// so at depth d it spans |x| <= d. Boxes x = 0 and 3 (|x| <= 3.5 at depth 3.5..4.5) are in
// view, x = 6 (5.5 > 4.5) is not; of the row, chunk 0 (x -0.5..510.5) at depth 9.5..10.5 is,
// chunk 1 (x from 511.5) is not. Drawn: 2 + 1 of 14 chunks, 24 + 3072 of 12408 triangles.
TEST(ViewerCulling, SkipsTheChunksOutsideTheView) {
  OffscreenContext context;
  Scene scene;
  scene.source_path = "boxes (in code)";
  const int grey = add_grey(scene, 0.5f);
  for (int i = 0; i < 10; ++i) {
    const float x = 3.0f * float(i);
    scene.meshes.push_back(
        test::make_box({x - 0.5f, -0.5f, -4.5f}, {x + 0.5f, 0.5f, -3.5f}, grey, false));
  }
  Mesh row = box_row(1024, grey);
  for (vec3& p : row.positions) p.z -= 10.0f;
  scene.meshes.push_back(row);
  Renderer renderer;
  renderer.set_scene(scene);
  ViewCamera camera;
  camera.position = vec3(0.0f);
  camera.target = {0.0f, 0.0f, -1.0f};
  camera.vertical_fov_deg = 90.0f;
  renderer.set_culling({});
  renderer.render_flat(camera, 100, 100);
  const DrawCounts& counts = renderer.stats().view;
  EXPECT_EQ(counts.chunks_total, 14);
  EXPECT_EQ(counts.chunks_drawn, 3);
  EXPECT_EQ(counts.triangles_total, 12408u);
  EXPECT_EQ(counts.triangles_drawn, 24u + 3072u);
  EXPECT_EQ(counts.draw_calls, 3);
  renderer.render(camera, 100, 100, RenderSettings{});
  EXPECT_EQ(renderer.stats().view.chunks_drawn, 3);
  EXPECT_EQ(renderer.stats().view.triangles_drawn, 24u + 3072u);
  renderer.set_culling({false, false, false});
  renderer.render_flat(camera, 100, 100);
  EXPECT_EQ(renderer.stats().view.chunks_drawn, 14);
  EXPECT_EQ(renderer.stats().view.triangles_drawn, 12408u);
}

// Three closed rooms in a row (x = -2..2, 3..7, 8..12), each with a ceiling light and a block,
// and 200 small boxes outside in front of them (z = 3..5).
Scene three_rooms() {
  Scene scene;
  scene.source_path = "three rooms (in code)";
  const int grey = add_grey(scene, 0.6f);
  const int lamp_id = add_lamp(scene);
  for (int r = 0; r < 3; ++r) {
    const float x = 5.0f * float(r);
    scene.meshes.push_back(test::make_box({x - 2, 0, -2}, {x + 2, 3, 2}, grey, true, "room"));
    scene.meshes.push_back(
        test::make_quad({x - 0.5f, 2.98f, -0.5f}, {1, 0, 0}, {0, 0, 1}, lamp_id, "light"));
    scene.meshes.push_back(
        test::make_box({x + 0.3f, 0, -0.8f}, {x + 1.0f, 1.0f, -0.1f}, grey, false, "block"));
  }
  for (int i = 0; i < 200; ++i) {
    const float x = 0.07f * float(i) - 2.0f, z = 3.0f + 0.5f * float(i % 5);
    scene.meshes.push_back(test::make_box({x, 0, z}, {x + 0.05f, 0.3f, z + 0.05f}, grey, false));
  }
  return scene;
}

// The shadow cubes with occlusion culling draw fewer triangles (the walls hide the rest) and
// give the same bits, seen from inside rooms 0 and 1, where every other light's cubes must
// still see the walls that shadow it.
TEST(ViewerCulling, ShadowCubeOcclusionSameBits) {
  OffscreenContext context;
  const Scene scene = three_rooms();
  Renderer renderer;
  renderer.set_culling({true, true, false});
  renderer.set_scene(scene);
  const DrawCounts frustum_only = renderer.stats().shadow_cubes_drawn;
  std::vector<Image> off;
  ViewCamera cameras[2];
  for (int r = 0; r < 2; ++r) {
    cameras[r].position = {5.0f * float(r) - 1.5f, 1.6f, 1.5f};
    cameras[r].target = {5.0f * float(r) + 0.6f, 0.5f, -0.5f};
    cameras[r].vertical_fov_deg = 70.0f;
    renderer.render(cameras[r], kWidth, kHeight, RenderSettings{});
    off.push_back(renderer.read_radiance());
  }
  renderer.set_culling({});
  renderer.set_scene(scene);
  const DrawCounts occluded = renderer.stats().shadow_cubes_drawn;
  EXPECT_EQ(occluded.triangles_total, frustum_only.triangles_total);
  EXPECT_LT(occluded.triangles_drawn, frustum_only.triangles_drawn / 2);
  std::printf("shadow cube triangles drawn: %zu with occlusion, %zu frustum only, of %zu\n",
              occluded.triangles_drawn, frustum_only.triangles_drawn, occluded.triangles_total);
  for (int r = 0; r < 2; ++r) {
    renderer.render(cameras[r], kWidth, kHeight, RenderSettings{});
    const Image on = renderer.read_radiance();
    EXPECT_TRUE(same_bits(on, off[size_t(r)])) << "room " << r;
    EXPECT_GT(pixel_sum(on), 0.0);
  }
}

// Camera-pass occlusion culling (Renderer::Culling::camera_occlusion) gives the same bits as
// the pre-pass without it, in full and stochastic mode and in the flat frame: from inside
// rooms 0 and 1 (the walls hide everything else), from outside in front of the boxes (rooms
// and boxes in view, some boxes behind others) and from above (the rooms' roofs hide their
// insides). Inside, looking through two walls at the boxes and the next rooms, it draws the
// room's own triangles only.
TEST(ViewerCulling, CameraOcclusionSameBits) {
  OffscreenContext context;
  const Scene scene = three_rooms();
  Renderer renderer;
  renderer.set_scene(scene);
  const View views[] = {{"room 0", {-1.5f, 1.6f, -1.5f}, {1.8f, 1.0f, 1.5f}},
                        {"room 1", {3.5f, 1.6f, -1.5f}, {6.8f, 1.0f, 1.5f}},
                        {"outside", {4.0f, 1.0f, 8.0f}, {4.0f, 0.5f, 0.0f}},
                        {"above", {5.0f, 9.0f, 6.0f}, {5.0f, 0.0f, 0.0f}}};
  Renderer::Culling without, always;
  without.camera_occlusion = false;
  always.camera_occlusion_every_frame = true;  // from outside and above they hide little
  for (const View& view : views) {
    const ViewCamera camera = camera_for(view, 70.0f);
    const bool inside = std::string(view.name).starts_with("room");
    Image full_off;
    for (const RenderSettings& settings : {RenderSettings{}, stochastic_settings()}) {
      const Image off = render(renderer, camera, without, settings);
      if (settings.direct_mode == DirectMode::full) full_off = off;
      const size_t drawn_off = renderer.stats().view.triangles_drawn;
      const Image on = render(renderer, camera, always, settings);
      const DrawCounts counts = renderer.stats().view;
      EXPECT_TRUE(same_bits(off, on)) << view.name;
      EXPECT_GT(pixel_sum(on), 0.0) << view.name;  // not a blank image
      EXPECT_GT(renderer.stats().camera_occlusion_queries, 0) << view.name;
      EXPECT_LE(counts.triangles_drawn, drawn_off) << view.name;
      if (inside) {  // the room's own: walls 12, light 2, block 12
        EXPECT_EQ(counts.triangles_drawn, 26u) << view.name;
        EXPECT_GT(drawn_off, 1000u) << view.name;
      }
      std::printf("%s: %zu triangles drawn with camera occlusion, %zu without, of %zu\n",
                  view.name, counts.triangles_drawn, drawn_off, counts.triangles_total);
    }
    renderer.set_culling(without);
    renderer.render_flat(camera, kWidth, kHeight);
    const Image flat_off = renderer.read_radiance();
    renderer.set_culling(always);
    renderer.render_flat(camera, kWidth, kHeight);
    EXPECT_TRUE(same_bits(flat_off, renderer.read_radiance())) << view.name;
    // A still camera's refinement: each band's pre-pass and queries run under its scissor, and
    // after 1 + 2 frames the image is the full one.
    RenderSettings refine = stochastic_settings();
    refine.refine_bands = 2;
    for (int frame = 0; frame < 3; ++frame) renderer.render(camera, kWidth, kHeight, refine);
    EXPECT_TRUE(same_bits(full_off, renderer.read_radiance())) << view.name;
  }
}

// A closed room (x, z = -2..2, y = 0..3; 12 triangles, facing in) with a ceiling light (2
// triangles), and 200 boxes of 12 triangles outside beyond its +x wall (x = 4..23, z = -5..4,
// each its own mesh). The clusters' grid puts the room and light alone in the nearest cell
// (202 meshes, about 24 a cell: x centres 0..23.15 in 6 cells of 3.9 m, the boxes' from
// 4.15). From inside, looking at the +x wall with every box behind it (the light, 56 degrees
// up at its nearest, is outside the 70-degree view), the camera pass draws the room's 12
// triangles and nothing else; without camera occlusion it draws the boxes in the frustum too.
// Same bits either way.
TEST(ViewerCulling, CameraOcclusionDrawsOnlyTheRoom) {
  OffscreenContext context;
  Scene scene;
  scene.source_path = "a room and 200 boxes (in code)";
  const int grey = add_grey(scene, 0.6f);
  scene.meshes.push_back(test::make_box({-2, 0, -2}, {2, 3, 2}, grey, true, "room"));
  scene.meshes.push_back(
      test::make_quad({-0.5f, 2.98f, -0.5f}, {1, 0, 0}, {0, 0, 1}, add_lamp(scene), "light"));
  for (int i = 0; i < 200; ++i) {
    const float x = 4.0f + float(i % 20), z = -5.0f + float(i / 20);
    scene.meshes.push_back(test::make_box({x, 0, z}, {x + 0.3f, 0.3f, z + 0.3f}, grey, false));
  }
  Renderer renderer;
  renderer.set_scene(scene);
  const ViewCamera camera = camera_for({"room", {-1.5f, 1.5f, 0.0f}, {2.0f, 1.0f, 0.3f}}, 70.0f);
  Renderer::Culling without;
  without.camera_occlusion = false;
  const Image off = render(renderer, camera, without);
  const DrawCounts counts_off = renderer.stats().view;
  const Image on = render(renderer, camera, {});
  const DrawCounts counts = renderer.stats().view;
  EXPECT_EQ(counts.triangles_total, 14u + 2400u);
  EXPECT_EQ(counts.triangles_drawn, 12u);
  EXPECT_GT(counts_off.triangles_drawn, 14u + 12u * 100u);  // most boxes are in the frustum
  EXPECT_TRUE(same_bits(off, on));
  EXPECT_GT(pixel_sum(on), 0.0);
  renderer.render_flat(camera, kWidth, kHeight);
  EXPECT_EQ(renderer.stats().view.triangles_drawn, 12u);
  std::printf("room: %zu triangles drawn with camera occlusion (%d queries), %zu without\n",
              counts.triangles_drawn, renderer.stats().camera_occlusion_queries,
              counts_off.triangles_drawn);
}

// Five closed rooms side by side (x = -2..2 up to 14..18), each with a ceiling light, a block
// and 30 pebbles of 12 triangles (177 meshes, 2,230 triangles), seen from 25 m above the middle
// room: the grid's clusters hold a room's box with what stands in it, so a cluster's own box
// reaches its ceiling and the ceilings hide little. With the occluders first (the room boxes,
// lights and blocks: at most 12 triangles, at least 0.75 m long), a cluster that shows draws
// them and is tested again with the box of its other members, under the ceilings: the rooms
// and the nearest cluster (drawn untested) remain; the same bits as without camera occlusion.
// Measured: 1,930 triangles in the frustum, 1,748 drawn with the clusters alone, 308 with the
// occluders first.
TEST(ViewerCulling, OccludersFirstLetTheCeilingsHideTheRooms) {
  OffscreenContext context;
  Scene scene;
  scene.source_path = "five rooms seen from above (in code)";
  const int grey = add_grey(scene, 0.6f);
  const int lamp_id = add_lamp(scene);
  for (int r = 0; r < 5; ++r) {
    const float x = 4.0f * float(r);
    scene.meshes.push_back(test::make_box({x - 2, 0, -2}, {x + 2, 3, 2}, grey, true, "room"));
    scene.meshes.push_back(
        test::make_quad({x - 0.5f, 2.98f, -0.5f}, {1, 0, 0}, {0, 0, 1}, lamp_id, "light"));
    scene.meshes.push_back(
        test::make_box({x + 0.3f, 0, -0.8f}, {x + 1.0f, 1.0f, -0.1f}, grey, false, "block"));
    for (int i = 0; i < 30; ++i) {
      const float px = x - 1.8f + 0.6f * float(i % 6), pz = -1.5f + 0.6f * float(i / 6);
      scene.meshes.push_back(
          test::make_box({px, 0, pz}, {px + 0.1f, 0.1f, pz + 0.1f}, grey, false, "pebble"));
    }
  }
  Renderer renderer;
  renderer.set_scene(scene);
  const ViewCamera camera = camera_for({"above", {8.0f, 25.0f, 0.5f}, {8.0f, 0.0f, 0.0f}}, 60.0f);
  Renderer::Culling without, clusters_alone, occluders;
  without.camera_occlusion = false;
  clusters_alone.camera_occlusion_every_frame = true;
  clusters_alone.occluders_first = false;
  occluders.camera_occlusion_every_frame = true;
  RenderSettings roofs;  // the light is inside: from above, the reflectance shows the roofs
  roofs.term = Term::reflectance;
  const Image off = render(renderer, camera, without, roofs);
  const size_t drawn_off = renderer.stats().view.triangles_drawn;
  const Image alone = render(renderer, camera, clusters_alone, roofs);
  const size_t drawn_alone = renderer.stats().view.triangles_drawn;
  const Image on = render(renderer, camera, occluders, roofs);
  const size_t drawn_on = renderer.stats().view.triangles_drawn;
  std::printf("from above: %zu triangles drawn without camera occlusion, %zu with the clusters "
              "alone, %zu with the occluders first\n",
              drawn_off, drawn_alone, drawn_on);
  EXPECT_LT(drawn_on, drawn_alone / 4);
  EXPECT_GE(drawn_on, 5u * 12u);  // the five rooms' boxes at least
  EXPECT_TRUE(same_bits(off, alone));
  EXPECT_TRUE(same_bits(off, on));
  EXPECT_GT(pixel_sum(on), 0.0);
}

// The schedule alone: a losing probe waits kFirstWait frames, each further one twice as many
// up to kMaxWait, a win queries every frame again.
TEST(OcclusionSchedule, BacksOffAfterLosingProbesAndResumesAfterAWin) {
  OcclusionSchedule schedule;
  std::vector<int> waits;
  for (int probe = 0; probe < 6; ++probe) {
    ASSERT_TRUE(schedule.query());
    schedule.frame_done(true, 1.0, 100.0);  // 1 % hidden: not worth it
    waits.push_back(schedule.frames_to_wait());
    while (!schedule.query()) schedule.frame_done(false, 0.0, 0.0);
  }
  EXPECT_EQ(waits, (std::vector<int>{4, 8, 16, 32, 32, 32}));
  schedule.frame_done(true, 25.0, 100.0);  // exactly kWorthwhile
  EXPECT_TRUE(schedule.query());
  schedule.frame_done(true, 24.0, 100.0);
  EXPECT_EQ(schedule.frames_to_wait(), 4);  // the back-off starts again from the first wait
}

// A moving camera's frames with the default schedule (Culling::camera_occlusion_every_frame
// off) against camera occlusion off, frame by frame the same bits, while the schedule switches:
// in room 0 (26 of 2,478 triangles drawn) each frame queries; above the rooms (nothing hidden)
// the first frame queries and loses, 4 frames skip, a probe loses; back in room 0 the next 8
// frames skip (drawing what the frustum holds), then a probe wins and every frame queries
// again. Each frame moves the camera 1 cm, so each is a stochastic first frame.
TEST(ViewerCulling, CameraOcclusionScheduleSameBitsAcrossSwitches) {
  OffscreenContext context;
  const Scene scene = three_rooms();
  Renderer scheduled, reference;
  scheduled.set_scene(scene);
  reference.set_scene(scene);
  Renderer::Culling without;
  without.camera_occlusion = false;
  reference.set_culling(without);
  const View room{"room 0", {-1.5f, 1.6f, -1.5f}, {1.8f, 1.0f, 1.5f}};
  const View above{"above", {5.0f, 9.0f, 6.0f}, {5.0f, 0.0f, 0.0f}};
  std::vector<const View*> path(2, &room);
  path.insert(path.end(), 6, &above);
  path.insert(path.end(), 10, &room);
  const std::string expected = "QQQ----Q--------QQ";  // Q: the frame queried
  std::string queried;
  for (size_t f = 0; f < path.size(); ++f) {
    View view = *path[f];
    view.position.x += 0.01f * float(f);
    const ViewCamera camera = camera_for(view, 70.0f);
    scheduled.render(camera, kWidth, kHeight, stochastic_settings());
    reference.render(camera, kWidth, kHeight, stochastic_settings());
    const Image on = scheduled.read_radiance();
    EXPECT_TRUE(same_bits(on, reference.read_radiance())) << "frame " << f;
    EXPECT_GT(pixel_sum(on), 0.0) << "frame " << f;
    const FrameStats& stats = scheduled.stats();
    queried += stats.camera_occlusion_queried ? 'Q' : '-';
    EXPECT_EQ(stats.camera_occlusion_queries > 0, stats.camera_occlusion_queried) << f;
    if (path[f] == &room) {  // the room's own 26 when queried, what the frustum holds if not
      EXPECT_EQ(stats.view.triangles_drawn,
                stats.camera_occlusion_queried ? 26u : reference.stats().view.triangles_drawn)
          << "frame " << f;
    }
  }
  EXPECT_EQ(queried, expected);
  // render_flat follows the same schedule: a winning room frame queried, so this one does.
  scheduled.render_flat(camera_for(room, 70.0f), kWidth, kHeight);
  EXPECT_TRUE(scheduled.stats().camera_occlusion_queried);
  EXPECT_EQ(scheduled.stats().view.triangles_drawn, 26u);
}

}  // namespace
}  // namespace lb
