// The HQ renderer: the paper's sum L = R (direct + map + radiosity), mirrors and glass,
// determinism across thread counts, the thin-lens camera.

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstring>
#include <numbers>

#include "bake/bsdf.h"
#include "bake/transport/baked_terms.h"
#include "bake/hq/hq_render.h"
#include "bake/hq/ray_report.h"
#include "bake/thin_lens_camera.h"
#include "hq_scenes.h"
#include "test_helpers.h"

namespace lb {
namespace {

Camera looking(vec3 from, vec3 to, float fov = 40.0f) {
  Camera camera;
  camera.position = from;
  camera.target = to;
  camera.vertical_fov_deg = fov;
  return camera;
}

// A black emitter of radiance `emission` and a glass of index `ior`: their material indices.
int add_lamp(Scene& scene, vec3 emission) {
  Material lamp;
  lamp.emission = emission;
  lamp.reflectance = vec3(0.0f);
  return test::add_material(scene, lamp);
}
int add_glass(Scene& scene, float ior, vec3 reflectance = vec3(1.0f)) {
  Material glass;
  glass.kind = MaterialKind::glass;
  glass.ior = ior;
  glass.reflectance = reflectance;
  return test::add_material(scene, glass);
}

// A 4 x 4 m quad in the plane z = 0 facing +z, seen head-on from z = 2 so it fills the frame.
Scene quad_scene(vec3 reflectance) {
  Scene scene;
  Material wall;
  wall.reflectance = reflectance;
  const int material = test::add_material(scene, wall);
  scene.meshes.push_back(test::make_quad({-2, -2, 0}, {4, 0, 0}, {0, 4, 0}, material));
  return scene;
}

// (c) No lights, constant vertex radiance X and a constant illumination map M: every pixel is
// R (X + M), to float rounding (relative 1e-5), whatever the sampling.
TEST(HqRender, DiffuseReproducesReflectanceTimesBakedTerms) {
  const vec3 reflectance(0.7f, 0.5f, 0.25f);
  const Scene scene = quad_scene(reflectance);
  BakedScene baked = test::unbaked(scene);
  const vec3 radiosity(0.3f, 0.6f, 0.9f), caustic(0.2f, 0.1f, 0.05f);
  baked.vertex_radiance[0].assign(baked.scene.meshes[0].positions.size(), radiosity);
  IlluminationMaps maps;
  maps.width = 4;
  maps.height = 4;
  maps.radiance.assign(16, caustic);
  maps.valid.assign(16, 1);
  baked.illumination = &maps;
  baked.scene.meshes[0].lightmap_uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};

  HqParams params;
  params.width = 24;
  params.height = 16;
  params.samples_per_side = 2;
  const HqRenderer renderer(baked, params);
  HqStats stats;
  const std::vector<vec3> image = renderer.render(looking({0, 0, 2}, {0, 0, 0}), 1, stats);
  const vec3 expected = reflectance * (radiosity + caustic);
  for (const vec3& pixel : image)
    for (int c = 0; c < 3; ++c) ASSERT_NEAR(pixel[c], expected[c], 1e-5f * expected[c]);
  EXPECT_EQ(stats.rays.viewing, uint64_t(24 * 16 * 4));
  EXPECT_EQ(stats.rays.shadow, 0u);  // no lights: no shadow rays
}

// Varying terms are interpolated, not averaged: vertex radiance 0 at x = -2 and 1 at x = +2
// must give R * (x + 2) / 4 at every pixel centre's hit point (bilinear over the quad).
TEST(HqRender, VertexRadiosityIsInterpolatedBarycentrically) {
  const Scene scene = quad_scene(vec3(0.5f));
  BakedScene baked = test::unbaked(scene);
  baked.vertex_radiance[0] = {vec3(0), vec3(1), vec3(1), vec3(0)};  // corners -x, +x, +x, -x
  SurfacePoint sp;
  sp.mesh = 0;
  for (float b1 : {0.0f, 0.25f, 0.6f}) {
    sp.triangle = 0;  // (0, 1, 2): radiance (0, 1, 1)
    sp.barycentric = {b1, 0.2f};
    EXPECT_NEAR(vertex_radiosity_at(baked, sp).x, b1 + 0.2f, 1e-6f);
  }
}

// The atlas lookup is bilinear between texel centres and skips invalid texels.
TEST(HqRender, IlluminationMapBilinearSkipsGutter) {
  IlluminationMaps maps;
  maps.width = 2;
  maps.height = 1;
  maps.radiance = {vec3(1.0f), vec3(3.0f)};
  maps.valid = {1, 1};
  EXPECT_NEAR(illumination_map_at(maps, {0.5f, 0.5f}).x, 2.0f, 1e-6f);   // halfway
  EXPECT_NEAR(illumination_map_at(maps, {0.25f, 0.5f}).x, 1.0f, 1e-6f);  // texel centre
  EXPECT_NEAR(illumination_map_at(maps, {0.0f, 0.5f}).x, 1.0f, 1e-6f);   // clamped
  maps.valid = {1, 0};
  EXPECT_NEAR(illumination_map_at(maps, {0.6f, 0.5f}).x, 1.0f, 1e-6f);  // gutter ignored
}

// The three terms together at one point: a 1-pixel, narrow-field render of a floor point under
// a square light, with radiosity X and map M: R (E/pi + X + M) within 1.5% (E from Lambert's
// formula; 64 passes x 16 spp = 1024 one-shadow-ray samples, stratified).
TEST(HqRender, SumsDirectMapAndRadiosity) {
  Scene scene;
  Material floor;
  floor.reflectance = vec3(0.5f);
  const int floor_material = test::add_material(scene, floor);
  Material lamp;
  lamp.emission = vec3(10.0f);
  lamp.reflectance = vec3(0.0f);
  const int lamp_material = test::add_material(scene, lamp);
  scene.meshes.push_back(test::make_quad({-5, 0, 5}, {10, 0, 0}, {0, 0, -10}, floor_material));
  scene.meshes.push_back(
      test::make_quad({-0.25f, 1, -0.25f}, {0.5f, 0, 0}, {0, 0, 0.5f}, lamp_material));
  BakedScene baked = test::unbaked(scene);
  const vec3 radiosity(0.05f), caustic(0.02f);
  baked.vertex_radiance[0].assign(4, radiosity);
  IlluminationMaps maps;
  maps.width = maps.height = 1;
  maps.radiance = {caustic};
  maps.valid = {1};
  baked.illumination = &maps;
  baked.scene.meshes[0].lightmap_uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};

  HqParams params;
  params.width = params.height = 1;
  const HqRenderer renderer(baked, params);
  HqStats stats;
  // A camera looking straight down at the origin with a tiny field: every ray hits ~(0,0,0).
  Camera camera = looking({0.0f, 0.5f, 0.0f}, {0, 0, 0}, 0.01f);
  camera.up = {0, 0, -1};
  const std::vector<vec3> image = renderer.render(camera, 64, stats);
  // Lambert: a 0.5 m square 1 m above the point, centred: E/pi = L * F, with the square form
  // factor F = 4 * (1/2pi) * 2 * a/sqrt(1+a^2) atan(a/sqrt(1+a^2)), a = 0.25.
  const double a = 0.25, s = std::sqrt(1 + a * a);
  const double form_factor = 4.0 / (2.0 * std::numbers::pi) * 2.0 * (a / s) * std::atan(a / s);
  const double expected = 0.5 * (10.0 * form_factor + 0.05 + 0.02);
  EXPECT_NEAR(image[0].x, expected, 0.015 * expected);
  EXPECT_LE(stats.rays.shadow, stats.rays.viewing);
  EXPECT_GT(stats.rays.shadow,
            stats.rays.viewing * 9 / 10);  // every viewing ray hits the lit floor
}

// (e) A mirror of reflectance Rm facing the camera, with a large emitter of radiance Le behind
// the camera facing the mirror: every pixel shows Rm * Le exactly. Seen in a mirror, a diffuse
// wall with radiosity X and reflectance Rw shows Rm * Rw * X.
TEST(HqRender, MirrorShowsReflectanceTimesWhatItReflects) {
  Scene scene;
  Material mirror;
  mirror.kind = MaterialKind::mirror;
  mirror.reflectance = vec3(0.9f, 0.7f, 0.5f);
  const int mirror_material = test::add_material(scene, mirror);
  Material lamp;
  lamp.emission = vec3(2.0f, 3.0f, 4.0f);
  lamp.reflectance = vec3(0.0f);
  const int lamp_material = test::add_material(scene, lamp);
  scene.meshes.push_back(test::make_quad({-5, -5, 0}, {10, 0, 0}, {0, 10, 0}, mirror_material));
  // Faces -z, towards the mirror; the camera at z = 2 is in front of it (cameras occlude nothing).
  scene.meshes.push_back(test::make_quad({-20, -20, 4}, {0, 40, 0}, {40, 0, 0}, lamp_material));
  const BakedScene baked = test::unbaked(scene);
  HqParams params;
  params.width = 16;
  params.height = 12;
  params.samples_per_side = 2;
  const HqRenderer renderer(baked, params);
  HqStats stats;
  const std::vector<vec3> image = renderer.render(looking({0, 0, 2}, {0, 0, 0}), 1, stats);
  const vec3 expected = mirror.reflectance * lamp.emission;
  for (const vec3& pixel : image)
    for (int c = 0; c < 3; ++c) ASSERT_NEAR(pixel[c], expected[c], 1e-5f * expected[c]);
  EXPECT_EQ(stats.rays.viewing, 2u * 16 * 12 * 4);  // camera ray + one bounce
}

TEST(HqRender, MirrorShowsReflectedDiffuseWall) {
  Scene scene;
  Material mirror;
  mirror.kind = MaterialKind::mirror;
  mirror.reflectance = vec3(0.8f);
  const int mirror_material = test::add_material(scene, mirror);
  Material wall;
  wall.reflectance = vec3(0.5f, 0.25f, 1.0f);
  const int wall_material = test::add_material(scene, wall);
  scene.meshes.push_back(test::make_quad({-5, -5, 0}, {10, 0, 0}, {0, 10, 0}, mirror_material));
  scene.meshes.push_back(test::make_quad({-20, -20, 4}, {0, 40, 0}, {40, 0, 0}, wall_material));
  BakedScene baked = test::unbaked(scene);
  baked.vertex_radiance[1].assign(4, vec3(1.0f, 2.0f, 0.5f));
  HqParams params;
  params.width = 8;
  params.height = 8;
  const HqRenderer renderer(baked, params);
  HqStats stats;
  const std::vector<vec3> image = renderer.render(looking({0, 0, 2}, {0, 0, 0}), 1, stats);
  const vec3 expected = vec3(0.8f) * wall.reflectance * vec3(1.0f, 2.0f, 0.5f);
  for (const vec3& pixel : image)
    for (int c = 0; c < 3; ++c) ASSERT_NEAR(pixel[c], expected[c], 1e-5f * expected[c]);
}

// Glass pane (ior 1.5, transmittance T) in front of an emitter, seen at normal incidence: the
// Fresnel-chosen branches average to Le T^2 (1-F)^2 / (1-F^2) (all internal reflections summed),
// F = 0.04. 16x16 pixels x 64 spp = 16,384 paths: binomial sd 0.2%; tolerance 1%.
TEST(HqRender, GlassPaneTransmitsWithFresnel) {
  Scene scene;
  const int glass_material = add_glass(scene, 1.5f, vec3(0.9f));
  const int lamp_material = add_lamp(scene, vec3(1.0f));
  scene.meshes.push_back(test::make_box({-5, -5, -0.1f}, {5, 5, 0.0f}, glass_material, false));
  scene.meshes.push_back(test::make_quad({-50, -50, -3}, {100, 0, 0}, {0, 100, 0}, lamp_material));
  const BakedScene baked = test::unbaked(scene);
  HqParams params;
  params.width = 16;
  params.height = 16;
  const HqRenderer renderer(baked, params);
  HqStats stats;
  const std::vector<vec3> image = renderer.render(looking({0, 0, 5}, {0, 0, 0}, 2.0f), 4, stats);
  double mean = 0.0;
  for (const vec3& pixel : image) mean += pixel.x / double(image.size());
  const double f = 0.04;
  const double expected = 0.81 * (1 - f) * (1 - f) / (1 - f * f);
  EXPECT_NEAR(mean, expected, 0.01 * expected);
}

// A glass pane seen head-on (F = 0.04) with a lamp of radiance 1 behind the camera: its
// reflection shows the lamp, its refraction the black beyond, so each pixel is the share of
// its samples that reflect. The first bounce's choice is stratified over the pixel's 256
// samples (one pass of 16 x 16), so in every pixel that share is within 1/256 of F; drawn at
// random it would spread by sqrt(F (1 - F) / 256) = 0.012, three times that bound.
TEST(HqRender, GlassSplitsEveryPixelsSamplesInFresnelsProportion) {
  Scene scene;
  const int glass_material = add_glass(scene, 1.5f);
  const int lamp_material = add_lamp(scene, vec3(1.0f));
  scene.meshes.push_back(test::make_quad({-5, -5, 0}, {10, 0, 0}, {0, 10, 0}, glass_material));
  scene.meshes.push_back(test::make_quad({-50, -50, 10}, {0, 100, 0}, {100, 0, 0}, lamp_material));
  const BakedScene baked = test::unbaked(scene);
  HqParams params;
  params.width = params.height = 16;
  params.samples_per_side = 16;
  const HqRenderer renderer(baked, params);
  HqStats stats;
  const std::vector<vec3> image = renderer.render(looking({0, 0, 5}, {0, 0, 0}, 2.0f), 1, stats);
  const float f = fresnel_dielectric(1.0f, 1.0f / 1.5f);  // within 1e-5 over the 2 deg view
  ASSERT_NEAR(f, 0.04f, 1e-4f);
  for (const vec3& pixel : image) EXPECT_NEAR(pixel.x, f, 1.0f / 256.0f + 1e-4f);
}

// An emitter shows its radiance on its front side only.
TEST(HqRender, EmitterShowsRadianceOnFrontSide) {
  Scene scene;
  const int lamp_material = add_lamp(scene, vec3(3.0f));
  scene.meshes.push_back(test::make_quad({-2, -2, 0}, {4, 0, 0}, {0, 4, 0}, lamp_material));
  const BakedScene baked = test::unbaked(scene);
  HqParams params;
  params.width = params.height = 4;
  params.samples_per_side = 1;
  const HqRenderer renderer(baked, params);
  HqStats stats;
  EXPECT_EQ(renderer.render(looking({0, 0, 2}, {0, 0, 0}), 1, stats)[5], vec3(3.0f));
  EXPECT_EQ(renderer.render(looking({0, 0, -2}, {0, 0, 0}), 1, stats)[5], vec3(0.0f));
}

// (d) Same seed: same bits, with 1 thread and with 4; another seed: a different image.
TEST(HqRender, DeterministicAcrossThreadCounts) {
  const Scene scene = test::make_light_grid_room(3);
  const BakedScene baked = test::unbaked(scene);
  HqParams params;
  params.width = 48;
  params.height = 32;
  params.samples_per_side = 2;
  params.tile_size = 8;
  const HqRenderer renderer(baked, params);
  auto render_with = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
    HqStats stats;
    return renderer.render(scene.cameras[0], 2, stats);
  };
  const std::vector<vec3> one = render_with(1);
  const std::vector<vec3> four = render_with(4);
  const std::vector<vec3> again = render_with(2);
  ASSERT_EQ(one.size(), four.size());
  EXPECT_EQ(std::memcmp(one.data(), four.data(), one.size() * sizeof(vec3)), 0);
  EXPECT_EQ(std::memcmp(one.data(), again.data(), one.size() * sizeof(vec3)), 0);
  HqParams other = params;
  other.seed = 2;
  const HqRenderer other_renderer(baked, other);
  HqStats stats;
  const std::vector<vec3> different = other_renderer.render(scene.cameras[0], 2, stats);
  EXPECT_NE(std::memcmp(one.data(), different.data(), one.size() * sizeof(vec3)), 0);
}

// Progressive passes: two passes of 4 spp equal one film of 8 spp accumulated the same way,
// and the ray counts follow the paper's rule: at most one shadow ray per viewing path.
TEST(HqRender, ProgressivePassesAccumulate) {
  const Scene scene = test::make_light_grid_room(3);
  const BakedScene baked = test::unbaked(scene);
  HqParams params;
  params.width = 32;
  params.height = 24;
  params.samples_per_side = 2;
  const HqRenderer renderer(baked, params);
  Film film;
  HqStats stats;
  renderer.render_pass(scene.cameras[0], film, stats);
  const std::vector<vec3> first = film.average();
  renderer.render_pass(scene.cameras[0], film, stats);
  EXPECT_EQ(film.passes, 2);
  EXPECT_EQ(film.samples_per_pixel, 8u);
  EXPECT_EQ(stats.pass_seconds.size(), 2u);
  HqStats stats2;
  EXPECT_EQ(renderer.render(scene.cameras[0], 2, stats2), film.average());
  EXPECT_NE(first, film.average());
  EXPECT_EQ(stats.rays.samples, 2u * 32 * 24 * 4);
  EXPECT_LE(stats.rays.shadow, stats.rays.samples);
  EXPECT_GT(stats.rays.shadow, stats.rays.samples / 2);
  const RayTable table = make_ray_table(stats.rays, nullptr);
  EXPECT_EQ(table.total(), stats.rays.viewing + stats.rays.shadow);
  EXPECT_NE(format_ray_table(table, "test").find("view rays"), std::string::npos);
}

// The per-pixel reused light choice and the paper's per-hit choice render the same image in
// expectation: nine-light room, 32 x 24 pixels x 256 spp each, image means within 1.5%
// (each mean's sampling error is ~0.3% here), and per-hit sends at most one shadow ray per path.
TEST(HqRender, ReusedLightChoiceMatchesPerHitChoice) {
  const Scene scene = test::make_light_grid_room(3);
  const BakedScene baked = test::unbaked(scene);
  HqParams params;
  params.width = 32;
  params.height = 24;
  params.samples_per_side = 16;
  double means[2] = {0.0, 0.0};
  for (int reuse = 0; reuse < 2; ++reuse) {
    params.reuse_light_choice = reuse == 1;
    const HqRenderer renderer(baked, params);
    HqStats stats;
    for (const vec3& pixel : renderer.render(scene.cameras[0], 1, stats))
      means[reuse] += double(luminance(pixel)) / double(params.width * params.height);
    EXPECT_LE(stats.rays.shadow, stats.rays.samples);
  }
  EXPECT_NEAR(means[1], means[0], 0.015 * means[0]);
}

// The nine-light room with a mirror on the back wall and a glass ball on the table, so paths
// bounce: specular bounces go round in waves, each path with its own random stream.
Scene specular_room() {
  Scene scene = test::make_light_grid_room(3);
  Material mirror;
  mirror.kind = MaterialKind::mirror;
  mirror.reflectance = vec3(0.9f);
  Material glass;
  glass.kind = MaterialKind::glass;
  glass.ior = 1.5f;
  glass.reflectance = vec3(0.95f);
  const int mirror_material = test::add_material(scene, mirror);
  const int glass_material = test::add_material(scene, glass);
  scene.meshes.push_back(
      test::make_quad({-1.5f, 0.5f, -2.98f}, {3, 0, 0}, {0, 2, 0}, mirror_material, "mirror"));
  scene.meshes.push_back(
      test::make_sphere({0.3f, 1.35f, 0.0f}, 0.35f, 12, 24, glass_material, false, "ball"));
  return scene;
}

// The tile waves render what one path at a time renders: trace() on independent uniform
// samples (per-hit light choice, no strata, 1024 per pixel) over the same pixels gives the same
// image mean within 1.5% (measured spread over seeds: 0.2% for the waves at 256 spp, 0.4% for
// this reference; the old path-at-a-time renderer's mean matched the waves' to 0.03%);
// specular bounces happen (> 5% more viewing rays than paths), and the waves are bit-identical
// for 1 and 2 threads.
TEST(HqRender, WavesMatchOnePathAtATime) {
  const Scene scene = specular_room();
  const BakedScene baked = test::unbaked(scene);
  HqParams params;
  params.width = 32;
  params.height = 24;
  params.samples_per_side = 16;
  const HqRenderer renderer(baked, params);
  auto render_with = [&](int threads, HqStats& stats) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
    return renderer.render(scene.cameras[0], 1, stats);
  };
  HqStats stats, stats_two;
  const std::vector<vec3> waves = render_with(1, stats);
  const std::vector<vec3> waves_two = render_with(2, stats_two);
  EXPECT_EQ(std::memcmp(waves.data(), waves_two.data(), waves.size() * sizeof(vec3)), 0);
  EXPECT_GT(stats.rays.viewing, stats.rays.samples + stats.rays.samples / 20);

  const ThinLensCamera camera(scene.cameras[0], params.width, params.height);
  const int spp = params.samples_per_side * params.samples_per_side;
  double wave_mean = 0.0, path_mean = 0.0;
  HqRayCounts counts;
  for (int y = 0; y < params.height; ++y)
    for (int x = 0; x < params.width; ++x) {
      Rng rng(hash_seed(99, uint64_t(y), uint64_t(x)));
      vec3 sum(0.0f);
      for (int s = 0; s < 4 * spp; ++s) {
        PathSamples samples;
        samples.light_select = rng.next_float();
        samples.light_point = glm::min(rng.next_2d(), vec2(0.99999994f));
        const Ray ray = camera.generate(vec2(float(x), float(y)) + rng.next_2d(), {0.5f, 0.5f});
        sum += renderer.trace(ray, samples, rng, counts);
      }
      path_mean += double(luminance(sum / float(4 * spp)));
      wave_mean += double(luminance(waves[size_t(y * params.width + x)]));
    }
  EXPECT_NEAR(wave_mean, path_mean, 0.015 * path_mean);
  EXPECT_LE(counts.shadow, uint64_t(params.width * params.height * 4 * spp));
}

TEST(HqRender, CancelLeavesFilmUntouched) {
  const Scene scene = test::make_light_grid_room(3);
  const BakedScene baked = test::unbaked(scene);
  HqParams params;
  params.width = 32;
  params.height = 24;
  const HqRenderer renderer(baked, params);
  std::atomic<bool> cancel{true};
  Progress progress;
  progress.cancel = &cancel;
  Film film(32, 24);
  HqStats stats;
  EXPECT_THROW(renderer.render_pass(scene.cameras[0], film, stats, progress), Cancelled);
  EXPECT_EQ(film.passes, 0);
  for (const vec3& v : film.sum) EXPECT_EQ(v, vec3(0.0f));
}

// The thin lens: rays through one film point meet at the plane of focus; a pinhole's centre
// ray goes to the target.
TEST(ThinLensCamera, RaysMeetOnPlaneOfFocus) {
  Camera camera = looking({1, 2, 3}, {1, 2, -2}, 60.0f);
  const ThinLensCamera pinhole(camera, 40, 30);
  const Ray centre = pinhole.generate({20, 15}, {0.3f, 0.7f});
  EXPECT_NEAR(glm::length(centre.direction - vec3(0, 0, -1)), 0.0f, 1e-6f);
  camera.aperture_radius = 0.1f;
  camera.focus_distance = 4.0f;
  const ThinLensCamera lens(camera, 40, 30);
  const vec2 film(7.5f, 21.25f);
  const Ray a = lens.generate(film, {0.1f, 0.2f});
  const Ray b = lens.generate(film, {0.9f, 0.6f});
  EXPECT_GT(glm::length(a.origin - b.origin), 0.05f);
  // Intersect each with the plane z = 3 - 4.
  const vec3 pa = a.origin + a.direction * ((-1.0f - a.origin.z) / a.direction.z);
  const vec3 pb = b.origin + b.direction * ((-1.0f - b.origin.z) / b.direction.z);
  EXPECT_NEAR(glm::length(pa - pb), 0.0f, 1e-5f);
}

}  // namespace
}  // namespace lb
