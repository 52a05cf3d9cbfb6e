// The whole bake and its directory: bake_scene runs both passes, save_bake/load_bake round-trip
// every bit, a bake refuses a different scene, a broken file names itself, a flipped bit in any
// file is refused by its checksum, and a cancelled bake leaves nothing behind.

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>

#include "bake/pipeline/bake.h"
#include "bake/pipeline/bake_io.h"
#include "bake/pipeline/bake_settings.h"
#include "bake/work_limits.h"
#include "scenes.h"
#include "test_helpers.h"

namespace lb {
namespace {

namespace fs = std::filesystem;

using test::same_bits;

Scene room_with_mirror() {
  return test::make_room_with_mirror();
}

BakeParams small_params() {
  BakeParams params;
  params.illumination.rays_per_zone_side = 16;
  params.radiosity.ray_budget = 200'000;
  params.seed = 5;
  return params;
}

// The scene baked with small_params and saved to the fresh output folder NAME; returns its path.
std::string saved_bake(const Scene& scene, const std::string& name) {
  const BakeResult bake = bake_scene(scene, small_params());
  const std::string dir = test::output_dir() + "/" + name;
  fs::remove_all(dir);
  save_bake(dir, scene, bake);
  return dir;
}

TEST(BakeIo, RoundTripKeepsEveryBit) {
  const Scene scene = room_with_mirror();
  const BakeParams params = small_params();
  const BakeResult bake = bake_scene(scene, params);
  ASSERT_GT(bake.illumination.width, 0);
  ASSERT_GT(bake.radiosity.stats.patch_count, 0u);
  // The radiosity meshes carry the atlas UVs of pass 1.
  EXPECT_EQ(bake.radiosity.meshes[0].mesh.lightmap_uvs.size(),
            bake.radiosity.meshes[0].mesh.positions.size());

  const std::string dir = test::output_dir() + "/bake_round_trip";
  fs::remove_all(dir);
  save_bake(dir, scene, bake, params);
  EXPECT_TRUE(fs::exists(dir + "/manifest.json"));
  EXPECT_TRUE(fs::exists(dir + "/illumination.exr"));
  // The manifest records every setting (read back exactly) and what the bake held.
  const BakeParams recorded = read_bake_settings(dir);
  for (const BakeSetting& setting : bake_settings())
    EXPECT_EQ(setting.get(recorded), setting.get(params)) << setting.key;
  {
    std::ifstream in(dir + "/manifest.json");
    const nlohmann::json memory = nlohmann::json::parse(in).at("memory");
    EXPECT_EQ(memory.at("triangles"), triangle_count(scene));
    EXPECT_EQ(memory.at("texels"),
              uint64_t(bake.illumination.width) * uint64_t(bake.illumination.height));
    const uint64_t peak = memory.at("peak_resident_bytes");
    EXPECT_GT(peak, uint64_t(1) << 20);
    EXPECT_LE(peak, peak_resident_bytes());  // the process's peak so far, never less
  }
  const BakeResult loaded = load_bake(dir, scene);

  EXPECT_EQ(loaded.seed, 5u);
  EXPECT_EQ(loaded.illumination.width, bake.illumination.width);
  EXPECT_EQ(loaded.illumination.height, bake.illumination.height);
  EXPECT_TRUE(same_bits(loaded.illumination.radiance, bake.illumination.radiance));
  EXPECT_TRUE(same_bits(loaded.illumination.texel_area, bake.illumination.texel_area));
  EXPECT_TRUE(same_bits(loaded.illumination.valid, bake.illumination.valid));
  ASSERT_EQ(loaded.illumination.lightmap_uvs.size(), bake.illumination.lightmap_uvs.size());
  ASSERT_EQ(loaded.illumination.vertex_splits.size(), bake.illumination.vertex_splits.size());
  size_t split_meshes = 0;
  for (size_t m = 0; m < bake.illumination.lightmap_uvs.size(); ++m) {
    EXPECT_TRUE(same_bits(loaded.illumination.lightmap_uvs[m], bake.illumination.lightmap_uvs[m]));
    const VertexSplit& a = loaded.illumination.vertex_splits[m];
    const VertexSplit& b = bake.illumination.vertex_splits[m];
    EXPECT_TRUE(same_bits(a.copied_from, b.copied_from)) << m;
    EXPECT_TRUE(same_bits(a.triangles, b.triangles)) << m;
    split_meshes += b.empty() ? 0 : 1;
  }
  EXPECT_GE(split_meshes, 1u) << "the ball should have been split into charts";
  ASSERT_EQ(loaded.radiosity.meshes.size(), bake.radiosity.meshes.size());
  for (size_t m = 0; m < bake.radiosity.meshes.size(); ++m) {
    const MeshRadiosity& a = loaded.radiosity.meshes[m];
    const MeshRadiosity& b = bake.radiosity.meshes[m];
    EXPECT_TRUE(same_bits(a.mesh.positions, b.mesh.positions)) << m;
    EXPECT_TRUE(same_bits(a.mesh.normals, b.mesh.normals)) << m;
    EXPECT_TRUE(same_bits(a.mesh.uvs, b.mesh.uvs)) << m;
    EXPECT_TRUE(same_bits(a.mesh.lightmap_uvs, b.mesh.lightmap_uvs)) << m;
    EXPECT_TRUE(same_bits(a.mesh.tangents, b.mesh.tangents)) << m;
    EXPECT_TRUE(same_bits(a.mesh.triangles, b.mesh.triangles)) << m;
    EXPECT_TRUE(same_bits(a.vertex_radiance, b.vertex_radiance)) << m;
    EXPECT_TRUE(same_bits(a.triangle_patch, b.triangle_patch)) << m;
    EXPECT_EQ(a.mesh.material, b.mesh.material);
    EXPECT_EQ(a.mesh.name, b.mesh.name);
  }
  EXPECT_EQ(loaded.radiosity.stats.rays, bake.radiosity.stats.rays);
  EXPECT_EQ(loaded.radiosity.stats.residual_fraction, bake.radiosity.stats.residual_fraction);
  EXPECT_EQ(loaded.illumination.stats.illumination_rays, bake.illumination.stats.illumination_rays);
  EXPECT_EQ(loaded.illumination.stats.rays_saved, bake.illumination.stats.rays_saved);
  EXPECT_EQ(loaded.radiosity.stats.power_absorbed, bake.radiosity.stats.power_absorbed);
  EXPECT_EQ(loaded.radiosity.stats.seconds, bake.radiosity.stats.seconds);

  // Saving again over the directory replaces it whole.
  save_bake(dir, scene, bake);
  EXPECT_NO_THROW(load_bake(dir, scene));
}

TEST(BakeIo, RefusesAnotherSceneAndNamesBrokenFiles) {
  const Scene scene = room_with_mirror();
  const std::string dir = saved_bake(scene, "bake_mismatch");

  Scene moved = scene;
  moved.meshes[1].positions[0].x += 0.01f;
  try {
    load_bake(dir, moved);
    FAIL() << "a moved block must not load";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("different scene"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("manifest.json"), std::string::npos) << e.what();
  }
  Scene fewer = scene;
  fewer.meshes.pop_back();
  EXPECT_THROW(load_bake(dir, fewer), std::runtime_error);

  // Truncate radiosity.bin: its checksum names the file.
  const std::string bin = dir + "/radiosity.bin";
  fs::resize_file(bin, fs::file_size(bin) / 2);
  try {
    load_bake(dir, scene);
    FAIL() << "a truncated file must not load";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("radiosity.bin: checksum mismatch"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(load_bake(test::output_dir() + "/no_such_bake", scene), std::runtime_error);
}

// A vertex split that does not fit the scene's mesh (an index past its vertices) is refused
// with the file and mesh named, before anything reads out of bounds.
TEST(BakeIo, RefusesAVertexSplitThatDoesNotFitTheMesh) {
  const Scene scene = room_with_mirror();
  BakeResult bake = bake_scene(scene, small_params());
  const size_t ball = scene.meshes.size() - 1;
  ASSERT_FALSE(bake.illumination.vertex_splits[ball].empty());
  bake.illumination.vertex_splits[ball].copied_from[0] =
      uint32_t(scene.meshes[ball].positions.size());
  const std::string dir = test::output_dir() + "/bake_bad_split";
  fs::remove_all(dir);
  save_bake(dir, scene, bake);
  try {
    load_bake(dir, scene);
    FAIL() << "a split past the mesh's vertices must not load";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("illumination.bin"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("'ball'"), std::string::npos) << e.what();
  }
}

// Issue 42: before checksums, of 30 flipped bits in radiosity.bin or illumination.bin 9 loaded
// as silently different light. Now every flip in every file of the bake (the .bin files by
// their own checksums, the maps by the manifest's) is refused with one line naming the file.
TEST(BakeIo, EveryFlippedBitIsRefusedNamingTheFile) {
  const Scene scene = room_with_mirror();
  const std::string dir = saved_bake(scene, "bake_bit_flips");
  const auto write = [](const std::string& path, const std::string& bytes) {
    std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
  };
  std::mt19937_64 random(42);
  for (const char* name :
       {"illumination.bin", "radiosity.bin", "illumination.exr", "soft_light.exr"}) {
    const std::string path = dir + "/" + name;
    const std::string original = test::read_bytes(path);
    ASSERT_FALSE(original.empty()) << path;
    for (int flip = 0; flip < 30; ++flip) {
      const size_t bit = size_t(random() % (original.size() * 8));
      std::string damaged = original;
      damaged[bit / 8] = char(damaged[bit / 8] ^ (1 << (bit % 8)));
      write(path, damaged);
      try {
        load_bake(dir, scene);
        ADD_FAILURE() << path << ": loads with bit " << bit << " flipped";
      } catch (const std::runtime_error& e) {
        const std::string what = e.what();
        EXPECT_TRUE(what.starts_with(path + ": ")) << what;
        EXPECT_NE(what.find("checksum"), std::string::npos) << what;
        EXPECT_EQ(what.find('\n'), std::string::npos) << what;
      }
    }
    write(path, original);
  }
  EXPECT_NO_THROW(load_bake(dir, scene));
}

// The bake in `dir` as an older version wrote it: `version` in its manifest, without the
// files entries `keys` (the newer files stay, unread).
void as_older_version(const std::string& dir, int version,
                      std::initializer_list<const char*> keys) {
  nlohmann::json manifest;
  std::ifstream(dir + "/manifest.json") >> manifest;
  manifest["version"] = version;
  for (const char* key : keys) manifest["files"].erase(key);
  std::ofstream(dir + "/manifest.json", std::ios::trunc) << manifest.dump(2);
}

// Issue 38: a bake with the `directional` setting saves the caustic map's L1 band (s = 1) and,
// on the room's flat-normal-mapped white surfaces, the soft map's band beside the maps, and
// loads both back bit for bit; the caustic map and the radiosity keep the bits of the bake
// without it, the soft map within 5e-3 (its gather reads the caustic band on bumped surfaces,
// below); the bands are in the bake's hash and its files' checksums; a missing band file is
// named; bakes of version 6 (the caustic band only) and 5 (no band) read as before.
TEST(BakeIo, DirectionalBandRoundTripsAndLeavesTheOtherTermsAlone) {
  Scene scene = room_with_mirror();
  test::add_flat_normal_map(scene, 0);  // the room's white surfaces take the soft band
  BakeParams params = small_params();
  const BakeResult plain = bake_scene(scene, params);
  params.illumination.directional = true;
  const BakeResult bake = bake_scene(scene, params);
  const IlluminationMaps& maps = bake.illumination;
  ASSERT_GT(maps.width, 0);
  for (const std::vector<vec3>& axis : maps.l1) ASSERT_EQ(axis.size(), maps.radiance.size());
  double band = 0.0;
  for (const vec3& v : maps.l1[0]) band += std::abs(double(v.x));
  EXPECT_GT(band, 0.0) << "the mirror's caustic should bring a band";
  // The soft map's band beside it (soft_band.h), de-ringed against the soft map.
  const SoftTexelMap& soft = bake.soft_texels;
  for (const std::vector<vec3>& axis : soft.l1) ASSERT_EQ(axis.size(), maps.radiance.size());
  double soft_band = 0.0;
  for (size_t k = 0; k < soft.radiance.size(); ++k)
    for (int c = 0; c < 3; ++c) {
      const float l1 = glm::length(vec3(soft.l1[0][k][c], soft.l1[1][k][c], soft.l1[2][k][c]));
      EXPECT_LE(l1, soft.radiance[k][c] * (1.0f + 1e-5f) + 1e-12f) << "texel " << k;
      soft_band += l1;
    }
  EXPECT_GT(soft_band, 0.0) << "the room's walls light each other from one side";
  EXPECT_GT(soft.band_rays, 0u);
  EXPECT_TRUE(plain.soft_texels.l1[0].empty());
  EXPECT_TRUE(same_bits(plain.illumination.radiance, maps.radiance));
  // The soft map's gather reads the caustic band at its hits on the (flat-)normal-mapped
  // walls, decoded at n = n0: the map there but for L1 . n0 where bilinear taps mix charts of
  // two planes (room corners). Measured: at most 1.7e-3 of a texel's soft light. Without bumps
  // under a caustic the map keeps every bit (SoftBand.KeepsTheMapsBitsAndTheThreadCounts).
  ASSERT_EQ(plain.soft_texels.radiance.size(), soft.radiance.size());
  double worst = 0.0;
  for (size_t k = 0; k < soft.radiance.size(); ++k)
    for (int c = 0; c < 3; ++c)
      worst = std::max(worst, std::abs(double(plain.soft_texels.radiance[k][c]) -
                                       double(soft.radiance[k][c])) /
                                  (double(soft.radiance[k][c]) + 1e-9));
  std::printf("soft map with and without the bands: worst texel %.2e of its light\n", worst);
  EXPECT_LT(worst, 5e-3);
  EXPECT_TRUE(same_bits(plain.radiosity.meshes[0].vertex_radiance,
                        bake.radiosity.meshes[0].vertex_radiance));
  EXPECT_NE(bake_hash(plain), bake_hash(bake));

  const std::string dir = test::output_dir() + "/bake_directional";
  fs::remove_all(dir);
  save_bake(dir, scene, bake, params);
  EXPECT_TRUE(read_bake_settings(dir).illumination.directional);
  const BakeResult loaded = load_bake(dir, scene);
  for (size_t a = 0; a < 3; ++a) EXPECT_TRUE(same_bits(loaded.illumination.l1[a], maps.l1[a]));
  for (size_t a = 0; a < 3; ++a) EXPECT_TRUE(same_bits(loaded.soft_texels.l1[a], soft.l1[a]));
  EXPECT_EQ(loaded.soft_texels.band_rays, soft.band_rays);
  EXPECT_TRUE(same_bits(loaded.illumination.l1_share, std::vector<float>(maps.radiance.size(), 1)));
  EXPECT_EQ(bake_hash(loaded), bake_hash(bake));
  // A damaged band is refused by its checksum, naming the file.
  const std::string path = dir + "/illumination_l1y.exr";
  const std::string original = test::read_bytes(path);
  std::string damaged = original;
  damaged[damaged.size() / 2] = char(damaged[damaged.size() / 2] ^ 4);
  std::ofstream(path, std::ios::binary | std::ios::trunc) << damaged;
  try {
    load_bake(dir, scene);
    ADD_FAILURE() << path << ": loads with a flipped bit";
  } catch (const std::runtime_error& e) {
    EXPECT_TRUE(std::string(e.what()).starts_with(path + ": ")) << e.what();
  }
  std::ofstream(path, std::ios::binary | std::ios::trunc) << original;
  // A missing soft band file: one line naming it.
  const std::string soft_path = dir + "/soft_light_l1z.exr";
  fs::rename(soft_path, soft_path + ".away");
  try {
    load_bake(dir, scene);
    ADD_FAILURE() << soft_path << ": loads without the file";
  } catch (const std::runtime_error& e) {
    EXPECT_TRUE(std::string(e.what()).starts_with(soft_path + ": ")) << e.what();
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
  }
  fs::rename(soft_path + ".away", soft_path);

  // Version 6 (the caustic band only): reads with the caustic band, without the soft one.
  as_older_version(dir, 6, {"soft_light_l1x_exr", "soft_light_l1y_exr", "soft_light_l1z_exr"});
  const BakeResult v6 = load_bake(dir, scene);
  EXPECT_TRUE(v6.soft_texels.l1[0].empty());
  EXPECT_TRUE(same_bits(v6.illumination.l1[0], maps.l1[0]));
  EXPECT_TRUE(make_baked_scene(scene, v6).directional);
  EXPECT_EQ(make_baked_scene(scene, v6).soft_l1, nullptr);

  // Version 5 (before the band): its manifest has no band entries and reads without a band.
  const std::string old_dir = saved_bake(scene, "bake_version5");
  as_older_version(old_dir, 5,
                   {"illumination_l1x_exr", "illumination_l1y_exr", "illumination_l1z_exr"});
  const BakeResult old = load_bake(old_dir, scene);
  EXPECT_TRUE(old.illumination.l1[0].empty());
  EXPECT_TRUE(old.illumination.l1_share.empty());
  EXPECT_FALSE(make_baked_scene(scene, old).directional);
  EXPECT_TRUE(make_baked_scene(scene, loaded).directional);
}

TEST(BakeIo, CancelledBakeThrows) {
  const Scene scene = room_with_mirror();
  std::atomic<bool> cancel{false};
  Progress progress;
  progress.cancel = &cancel;
  progress.report = [&](std::string_view stage, double fraction) {
    if (stage.starts_with("radiosity") && fraction > 0.1) cancel = true;
  };
  EXPECT_THROW(bake_scene(scene, small_params(), progress), Cancelled);
}

}  // namespace
}  // namespace lb
