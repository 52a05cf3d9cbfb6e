// The glTF export (bake/export/gltf_export.h, docs/export.md): a small baked room with a mirror
// and a ball (so it has caustics) is written, read back with tinygltf and with our own
// loader, and every exported quantity is compared with the bake and its lightmap
// (bake/lightmap/lightmap.h); the CLI's file safety, bad input and the snapshot round trip.

#include <gtest/gtest.h>
#include <tiny_gltf.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <glm/gtc/constants.hpp>

#include "bake/accel.h"
#include "bake/export/gltf_bake_read.h"
#include "bake/export/gltf_export.h"
#include "bake/io/scene_load.h"
#include "bake/lightmap/lightmap.h"
#include "bake/pipeline/bake.h"
#include "scenes.h"
#include "test_helpers.h"

namespace lb {
namespace {

namespace fs = std::filesystem;

struct Exported {
  Scene scene;
  BakeResult bake;
  Lightmap lightmap;         // what the export puts in the file (same seed, same bits)
  std::vector<Mesh> meshes;  // the scene meshes with the atlas's splits, as exported
  std::string path;
  GltfExportInfo info;
  tinygltf::Model model;
};

// One bake and one export shared by the tests below (the bake is the slow part).
const Exported& exported() {
  static const Exported* result = [] {
    auto* e = new Exported;
    e->scene = test::make_room_with_mirror();
    BakeParams params;
    params.illumination.rays_per_zone_side = 16;
    params.radiosity.ray_budget = 200'000;
    params.seed = 5;
    e->bake = bake_scene(e->scene, params);
    LightmapParams lightmap;
    lightmap.seed = e->bake.seed;
    e->lightmap = bake_lightmap(e->scene, e->bake, lightmap);
    for (size_t m = 0; m < e->scene.meshes.size(); ++m)
      e->meshes.push_back(mesh_with_lightmap(e->scene.meshes[m], e->bake.illumination, m));
    // One folder per process: ctest runs these tests as parallel processes, each with its own
    // export, and one emptying a shared folder broke another's write (seen in CI).
    const fs::path dir = fs::path(test::output_dir()) / "gltf_export" / std::to_string(::getpid());
    fs::remove_all(dir);
    fs::create_directories(dir);
    e->path = (dir / "room.glb").string();
    e->info = export_gltf(e->path, e->scene, e->bake);
    tinygltf::TinyGLTF loader;
    std::string err, warn;
    if (!loader.LoadBinaryFromFile(&e->model, &err, &warn, e->path))
      ADD_FAILURE() << "tinygltf: " << err;
    return e;
  }();
  return *result;
}

template <class T>
std::vector<T> accessor_data(const tinygltf::Model& model, int index) {
  const tinygltf::Accessor& accessor = model.accessors.at(size_t(index));
  const tinygltf::BufferView& view = model.bufferViews.at(size_t(accessor.bufferView));
  const auto& buffer = model.buffers.at(size_t(view.buffer)).data;
  std::vector<T> out(accessor.count);
  const size_t offset = view.byteOffset + accessor.byteOffset;
  EXPECT_LE(offset + out.size() * sizeof(T), buffer.size());
  std::memcpy(out.data(), buffer.data() + offset, out.size() * sizeof(T));
  return out;
}

TEST(GltfExport, MeshesAndAccessorsMatchTheBake) {
  const Exported& e = exported();
  ASSERT_GT(e.bake.illumination.width, 0);
  const size_t meshes = e.meshes.size();
  ASSERT_EQ(e.model.meshes.size(), meshes);  // every mesh of the room is non-empty
  EXPECT_EQ(e.info.meshes, meshes);
  size_t with_map = 0;
  for (size_t m = 0; m < meshes; ++m) {
    const Mesh& mesh = e.meshes[m];
    ASSERT_EQ(e.model.meshes[m].primitives.size(), 1u);
    const tinygltf::Primitive& p = e.model.meshes[m].primitives[0];
    const size_t n = mesh.positions.size();
    // The scene's own surface (with the atlas's splits), not the refined radiosity mesh.
    EXPECT_EQ(mesh.triangles.size(), e.scene.meshes[m].triangles.size());
    EXPECT_EQ(e.model.accessors[size_t(p.attributes.at("POSITION"))].count, n) << mesh.name;
    EXPECT_TRUE(
        test::same_bits(accessor_data<vec3>(e.model, p.attributes.at("POSITION")), mesh.positions))
        << mesh.name;
    const auto indices = accessor_data<uint32_t>(e.model, p.indices);
    ASSERT_EQ(indices.size(), mesh.triangles.size() * 3) << mesh.name;
    EXPECT_EQ(std::memcmp(indices.data(), mesh.triangles.data(), indices.size() * 4), 0)
        << mesh.name;
    // No COLOR_0: all the baked light is in the lightmap.
    EXPECT_FALSE(p.attributes.count("COLOR_0")) << mesh.name;
    // Every diffuse mesh has lightmap UVs (TEXCOORD_1), bit for bit the atlas's.
    const bool diffuse = e.scene.materials[size_t(mesh.material)].is_diffuse();
    EXPECT_EQ(!mesh.lightmap_uvs.empty(), diffuse) << mesh.name;
    if (!mesh.lightmap_uvs.empty()) {
      ASSERT_TRUE(p.attributes.count("TEXCOORD_1")) << mesh.name;
      EXPECT_TRUE(test::same_bits(accessor_data<vec2>(e.model, p.attributes.at("TEXCOORD_1")),
                                  mesh.lightmap_uvs))
          << mesh.name;
      ++with_map;
    }
    if (!mesh.uvs.empty()) {
      EXPECT_TRUE(
          test::same_bits(accessor_data<vec2>(e.model, p.attributes.at("TEXCOORD_0")), mesh.uvs));
    }
    if (!mesh.normals.empty()) {
      const auto normals = accessor_data<vec3>(e.model, p.attributes.at("NORMAL"));
      for (size_t i = 0; i < n; ++i)
        ASSERT_NEAR(glm::length(normals[i]), 1.0f, 1e-5f) << mesh.name << " vertex " << i;
    }
  }
  EXPECT_EQ(with_map, e.info.lightmapped_meshes);
  EXPECT_GE(with_map, meshes - 2);  // all but the mirror and the glass ball
  EXPECT_EQ(e.model.cameras.size(), e.scene.cameras.size());
  EXPECT_EQ(e.model.asset.extras.Get("lightbake_lightmap_contents").Get<std::string>(), "indirect");
  EXPECT_NEAR(e.model.asset.extras.Get("lightbake_texel_density_per_m").GetNumberAsDouble(),
              1.0 / e.bake.illumination.texel_size, 1e-3 / e.bake.illumination.texel_size);
  for (const tinygltf::Camera& camera : e.model.cameras)
    EXPECT_GT(camera.perspective.zfar, camera.perspective.znear);  // finite: the validator
}

TEST(GltfExport, LightmapPngDecodesWithinItsStatedPrecision) {
  const Exported& e = exported();
  const Lightmap& maps = e.lightmap;
  ASSERT_EQ(e.model.images.size(), 1u);  // the room has no textures: only the lightmap
  const tinygltf::Image& image = e.model.images[0];
  ASSERT_EQ(image.width, maps.width);
  ASSERT_EQ(image.height, maps.height);
  ASSERT_GE(image.component, 3);
  const float scale = e.info.map_scale;
  float largest = 0.0f;
  for (const vec3& r : maps.radiance) largest = std::max({largest, r.x, r.y, r.z});
  EXPECT_EQ(scale, largest);  // nothing clips

  // Every texel decodes to the nearest 8-bit sRGB code of radiance / scale: the true value
  // lies inside the decoded code's rounding interval. Also measured: the worst relative error
  // over values >= 1% of the scale, and the worst absolute error in units of the scale.
  double worst_relative = 0.0, worst_absolute = 0.0;
  for (size_t i = 0; i < maps.radiance.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const int code = image.image[i * size_t(image.component) + size_t(c)];
      const float truth = maps.radiance[i][c] / scale;
      const float low = code == 0 ? 0.0f : srgb_eotf((float(code) - 0.5f) / 255.0f);
      const float high = code == 255 ? 1.0f : srgb_eotf((float(code) + 0.5f) / 255.0f);
      ASSERT_GE(truth, low - 1e-6f) << "texel " << i;
      ASSERT_LE(truth, high + 1e-6f) << "texel " << i;
      const double decoded = srgb_eotf(float(code) / 255.0f);
      worst_absolute = std::max(worst_absolute, std::abs(decoded - truth));
      if (truth >= 0.01f)
        worst_relative = std::max(worst_relative, std::abs(decoded - truth) / truth);
    }
  // Half a code step: 0.5 * (1 - eotf(254/255)) = 0.0045 at the top; relative at 1% of the
  // scale, 0.5 * (eotf(26/255) - eotf(25/255)) / 0.01 = 3.4%.
  std::printf(
      "lightmap %dx%d scale %.6g W/(sr m^2): worst |error| %.5f of scale, worst "
      "relative error above 1%% of scale %.4f\n",
      maps.width, maps.height, double(scale), worst_absolute, worst_relative);
  EXPECT_LE(worst_absolute, 0.0046);
  EXPECT_LE(worst_relative, 0.035);
  RecordProperty("worst_absolute_of_scale", std::to_string(worst_absolute));
  RecordProperty("worst_relative_above_1pct", std::to_string(worst_relative));
}

TEST(GltfExport, MozLightmapBindsTheMapWithUnits) {
  const Exported& e = exported();
  ASSERT_NE(std::find(e.model.extensionsUsed.begin(), e.model.extensionsUsed.end(), "MOZ_lightmap"),
            e.model.extensionsUsed.end());
  EXPECT_TRUE(e.model.extensionsRequired.empty());  // engines without it still load the file
  size_t bound = 0;
  for (const tinygltf::Mesh& mesh : e.model.meshes) {
    const tinygltf::Primitive& p = mesh.primitives[0];
    const tinygltf::Material& material = e.model.materials.at(size_t(p.material));
    const auto moz = material.extensions.find("MOZ_lightmap");
    // Bound exactly where the primitive has lightmap UVs.
    ASSERT_EQ(moz != material.extensions.end(), p.attributes.count("TEXCOORD_1") > 0) << mesh.name;
    if (moz == material.extensions.end()) continue;
    ++bound;
    const tinygltf::Value& v = moz->second;
    EXPECT_EQ(v.Get("texCoord").GetNumberAsInt(), 1);
    const int texture = v.Get("index").GetNumberAsInt();
    EXPECT_EQ(e.model.textures.at(size_t(texture)).source, 0);  // the lightmap image
    // E/pi stored: three.js needs pi; the 8-bit scale multiplies in.
    EXPECT_NEAR(v.Get("intensity").GetNumberAsDouble(),
                glm::pi<double>() * double(e.info.map_scale), 1e-9 * e.info.map_scale);
    const tinygltf::Value& extras = material.extras.Get("lightbake_lightmap");
    EXPECT_EQ(extras.Get("units").Get<std::string>(), "W/(sr m^2)");
    EXPECT_EQ(extras.Get("encoding").Get<std::string>(), "srgb8-scaled");
    EXPECT_NE(extras.Get("convention").Get<std::string>().find("E/pi"), std::string::npos);
    EXPECT_DOUBLE_EQ(extras.Get("scale").GetNumberAsDouble(), double(e.info.map_scale));
    EXPECT_EQ(extras.Get("hdr").Get<std::string>(), "room.lightmap.exr");
    EXPECT_EQ(extras.Get("contents").Get<std::string>(), "indirect");
    EXPECT_FALSE(extras.Get("includes_direct").Get<bool>());
    EXPECT_GT(extras.Get("texel_density_per_m").GetNumberAsDouble(), 1.0);
  }
  EXPECT_EQ(bound, e.info.lightmapped_meshes);
  EXPECT_GE(bound, 1u);
}

// RGBM (--lightmap-encoding rgbm) over six decades below the scale: every texel decodes, as the
// file's extras say, within half a code of its own multiplier (the closed bound of the
// encoding, docs/export.md), so each texel's largest channel keeps 8 bits at any brightness:
// relative error at most 0.5 / 128 wherever m > 1 (its rgb byte is then at least 128), where
// sRGB's codes are 3.4% apart at 1% of the scale and gone below 0.02%.
TEST(GltfExport, RgbmKeepsEightBitsAtEveryBrightness) {
  std::vector<vec3> radiance;
  for (int k = 0; k <= 600; ++k) {
    const float v = 20.0f * std::pow(10.0f, -6.0f * float(k) / 600.0f);  // 20 .. 2e-5
    radiance.push_back(vec3(v, 0.37f * v, 0.011f * v));
  }
  const LightmapPng map = encode_lightmap_png(int(radiance.size()), 1, radiance,
                                              LightmapEncoding::rgbm);
  ASSERT_EQ(map.channels, 4);
  EXPECT_EQ(map.scale, 20.0f);
  double worst_relative = 0.0;
  for (size_t i = 0; i < radiance.size(); ++i) {
    const uint8_t* texel = &map.bytes[i * 4];
    const vec3 decoded = decode_lightmap_texel(texel, LightmapEncoding::rgbm, map.scale);
    const float step = float(texel[3]) / 255.0f * map.scale / 255.0f;  // one rgb code
    for (int c = 0; c < 3; ++c)
      ASSERT_LE(std::abs(decoded[c] - radiance[i][c]), 0.5f * step * 1.0001f) << i << " " << c;
    if (texel[3] > 1)
      worst_relative =
          std::max(worst_relative, double(std::abs(decoded.x - radiance[i].x) / radiance[i].x));
  }
  EXPECT_LE(worst_relative, 0.5 / 128.0);
  // The PNG holds those bytes.
  const std::string path = test::fresh_dir("gltf_export", "rgbm") + "/map.png";
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(map.png.data()), std::streamsize(map.png.size()));
  const Image png = read_image(path);
  ASSERT_EQ(png.channels, 4);
  for (size_t i = 0; i < map.bytes.size(); ++i)
    ASSERT_EQ(unit_to_byte(png.pixels[i]), map.bytes[i]) << i;
}

TEST(GltfExport, ExrBesideHoldsTheMapInHalfFloat) {
  const Exported& e = exported();
  const Image exr = read_image(lightmap_exr_path(e.path));
  ASSERT_EQ(exr.width, e.lightmap.width);
  ASSERT_EQ(exr.height, e.lightmap.height);
  ASSERT_EQ(exr.channels, 3);
  // Half floats: 11 significant bits, relative error <= 2^-11 = 4.9e-4 (normal range).
  for (size_t i = 0; i < e.lightmap.radiance.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const float truth = e.lightmap.radiance[i][c];
      ASSERT_NEAR(exr.pixels[i * 3 + size_t(c)], truth, 4.9e-4f * truth + 1e-7f) << i;
    }
}

TEST(GltfExport, ReloadsThroughOurLoaderWithTheSameSurface) {
  const Exported& e = exported();
  // The glTF loader alone: load_scene would also cut the floor along the block (the scene
  // here is made in code, not conformed to its contacts: contact_conform.h).
  const LoadResult loaded = load_scene_gltf(e.path);
  // Our loader knows our own MOZ_lightmap: no warning at all.
  EXPECT_TRUE(loaded.warnings.empty()) << loaded.warnings.front();
  EXPECT_EQ(triangle_count(loaded.scene), triangle_count(e.scene));
  ASSERT_EQ(loaded.scene.meshes.size(), e.meshes.size());
  for (size_t m = 0; m < loaded.scene.meshes.size(); ++m) {
    const Material& original = e.scene.materials[size_t(e.meshes[m].material)];
    const Material& back = loaded.scene.materials[size_t(loaded.scene.meshes[m].material)];
    EXPECT_EQ(back.kind, original.kind) << e.meshes[m].name;
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(back.reflectance[c], original.reflectance[c], 1e-6f);
      EXPECT_NEAR(back.emission[c], original.emission[c], 1e-5f * original.emission[c]);
    }
    // TEXCOORD_1 comes back as the lightmap UVs.
    EXPECT_TRUE(test::same_bits(loaded.scene.meshes[m].lightmap_uvs, e.meshes[m].lightmap_uvs));
  }
  ASSERT_EQ(loaded.scene.cameras.size(), e.scene.cameras.size());
  for (size_t c = 0; c < e.scene.cameras.size(); ++c)  // the extras come back
    EXPECT_EQ(loaded.scene.cameras[c].exposure, e.scene.cameras[c].exposure);
}

TEST(GltfExport, TextGltfIsSelfContained) {
  const Exported& e = exported();
  const std::string path = (fs::path(e.path).parent_path() / "room_text.gltf").string();
  export_gltf(path, e.scene, e.bake);
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string err, warn;
  ASSERT_TRUE(loader.LoadASCIIFromFile(&model, &err, &warn, path)) << err;
  EXPECT_EQ(model.meshes.size(), e.model.meshes.size());
  EXPECT_EQ(model.accessors.size(), e.model.accessors.size());
  EXPECT_FALSE(fs::exists(fs::path(path).replace_extension(".bin")));  // data URIs
  EXPECT_TRUE(is_lightbake_gltf(path));
  EXPECT_TRUE(is_lightbake_gltf(e.path));
  EXPECT_FALSE(is_lightbake_gltf(test::source_dir() + "/tests/data/gltf/room.glb"));
}

// Materials and textures of the glTF fixtures come back through our loader as they went in.
void expect_round_trip(const std::string& fixture) {
  const LoadResult original = load_scene(test::source_dir() + "/tests/data/gltf/" + fixture);
  BakeParams params;
  params.illumination.rays_per_zone_side = 8;
  params.radiosity.ray_budget = 20'000;
  const BakeResult bake = bake_scene(original.scene, params);
  const fs::path dir = fs::path(test::output_dir()) / "gltf_export";
  fs::create_directories(dir);
  const std::string path = (dir / (fs::path(fixture).stem().string() + ".glb")).string();
  export_gltf(path, original.scene, bake);
  const LoadResult back = load_scene(path);
  ASSERT_EQ(back.scene.materials.size(), original.scene.materials.size()) << fixture;
  for (size_t i = 0; i < back.scene.materials.size(); ++i) {
    const Material& a = original.scene.materials[i];
    const Material& b = back.scene.materials[i];
    SCOPED_TRACE(fixture + ": material " + a.name);
    EXPECT_EQ(b.name, a.name);
    EXPECT_EQ(b.kind, a.kind);
    EXPECT_EQ(b.bump, a.bump);
    EXPECT_NEAR(b.bump_scale, a.bump_scale, 1e-6f);
    EXPECT_NEAR(b.ior, a.ior, 1e-6f);
    EXPECT_NEAR(b.roughness, a.roughness, 1e-6f);
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(b.reflectance[c], a.reflectance[c], 1e-6f);
      EXPECT_NEAR(b.emission[c], a.emission[c], 1e-6f * (1.0f + a.emission[c]));
    }
    EXPECT_EQ(b.reflectance_texture >= 0, a.reflectance_texture >= 0);
    EXPECT_EQ(b.alpha_mask, a.alpha_mask);
    EXPECT_EQ(b.alpha_blend, a.alpha_blend);
    if (a.reflectance_texture < 0 || b.reflectance_texture < 0) continue;
    const Texture& ta = original.scene.textures[size_t(a.reflectance_texture)];
    const Texture& tb = back.scene.textures[size_t(b.reflectance_texture)];
    EXPECT_EQ(tb.filter, ta.filter);  // the sampler comes back too
    EXPECT_EQ(tb.wrap_u, ta.wrap_u);
    EXPECT_EQ(tb.wrap_v, ta.wrap_v);
    ASSERT_EQ(tb.width, ta.width);
    ASSERT_EQ(tb.height, ta.height);
    ASSERT_EQ(tb.texels.size(), ta.texels.size());
    float worst = 0.0f;  // 8-bit sRGB in, 8-bit sRGB out: the same bytes, the same floats
    for (size_t t = 0; t < ta.texels.size(); ++t)
      worst = std::max(worst, std::abs(ta.texels[t] - tb.texels[t]));
    EXPECT_LE(worst, 1e-6f);
  }
  EXPECT_EQ(triangle_count(back.scene), triangle_count(original.scene));
  EXPECT_EQ(back.scene.cameras.size(), original.scene.cameras.size());
  for (size_t c = 0; c < std::min(back.scene.cameras.size(), original.scene.cameras.size()); ++c) {
    const Camera& a = original.scene.cameras[c];
    const Camera& b = back.scene.cameras[c];
    EXPECT_LT(glm::length(b.position - a.position), 1e-5f);
    EXPECT_NEAR(b.vertical_fov_deg, a.vertical_fov_deg, 1e-4f);
    EXPECT_GT(
        glm::dot(glm::normalize(b.target - b.position), glm::normalize(a.target - a.position)),
        0.99999f);
  }
}

TEST(GltfExport, FixtureMaterialsTexturesAndCamerasComeBack) {
  expect_round_trip("materials.gltf");      // diffuse, mirror, glossy, glass, emitters, normal map
  expect_round_trip("textured_quad.gltf");  // sRGB base colour texture, own TEXCOORD_1
  expect_round_trip("instanced.gltf");      // a camera
  // MASK and BLEND; a NEAREST sampler that clamps u and mirrors v
  expect_round_trip("alpha_leaf.glb");
}

// The fraction of 64 x 64 vertical rays from the floor under the leaf of
// test::make_masked_leaf_scene (x, z in [-0.5, 0.5]) that reach the sky.
double sky_seen_under_leaf(const Scene& scene) {
  const Accel accel(scene);
  constexpr int kSide = 64;
  int open = 0;
  for (int i = 0; i < kSide; ++i)
    for (int k = 0; k < kSide; ++k) {
      const vec3 p((float(i) + 0.5f) / kSide - 0.5f, 1e-3f, (float(k) + 0.5f) / kSide - 0.5f);
      open += !accel.occluded({p, vec3(0, 1, 0), 0.0f, 10.0f});
    }
  return double(open) / double(kSide * kSide);
}

// glTF alphaMode written back as read (docs/gltf.md, "Alpha"): a leaf cut by a 0/1 checker
// (MASK, its alpha in the base colour texture's fourth channel, white colour under its factor)
// and a pane of alpha 0.3 (BLEND, the factor alone). Read back, the leaf lets half the sky
// through, as before the round trip; the pane lets through 0.7 on average. Before: both
// exported OPAQUE, the leaf a solid shadow (0).
TEST(GltfExport, AlphaMaskAndBlendComeBackAndLetTheLightThrough) {
  Scene scene = test::make_masked_leaf_scene(3.0f);
  Material pane = scene.materials[size_t(scene.meshes[1].material)];
  pane.name = "pane", pane.alpha_mask = false, pane.alpha_blend = true;
  pane.alpha_texture = -1, pane.alpha_factor = 0.3f;
  scene.materials.push_back(pane);
  scene.meshes.push_back(test::make_quad({2.5f, 0.5f, 0.5f}, {1, 0, 0}, {0, 0, -1},
                                         int(scene.materials.size() - 1), "pane"));
  EXPECT_NEAR(sky_seen_under_leaf(scene), 0.5, 1e-9);
  BakeParams params;
  params.illumination.rays_per_zone_side = 4;
  params.radiosity.ray_budget = 10'000;
  const BakeResult bake = bake_scene(scene, params);
  const fs::path dir = fs::path(test::output_dir()) / "gltf_export" / std::to_string(::getpid());
  fs::create_directories(dir);
  const std::string path = (dir / "leaf.glb").string();
  export_gltf(path, scene, bake);
  const LoadResult back = load_scene_gltf(path);
  EXPECT_TRUE(back.warnings.empty()) << back.warnings.front();
  const Material& leaf = back.scene.materials[size_t(back.scene.meshes[1].material)];
  EXPECT_TRUE(leaf.alpha_mask);
  EXPECT_FALSE(leaf.alpha_blend);
  EXPECT_EQ(leaf.alpha_cutoff, 0.5f);
  ASSERT_GE(leaf.alpha_texture, 0);
  const Texture& alpha = back.scene.textures[size_t(leaf.alpha_texture)];
  EXPECT_EQ(alpha.texels, scene.textures[0].texels);  // 0 and 1 survive 8 bits exactly
  ASSERT_GE(leaf.reflectance_texture, 0);  // white, under the factor's 0.3
  EXPECT_EQ(back.scene.textures[size_t(leaf.reflectance_texture)].texels[0], 1.0f);
  EXPECT_NEAR(leaf.reflectance.x, 0.3f, 1e-6f);
  const Material& blended = back.scene.materials[size_t(back.scene.meshes[2].material)];
  EXPECT_TRUE(blended.alpha_blend);
  EXPECT_FALSE(blended.alpha_mask);
  EXPECT_EQ(blended.alpha_texture, -1);
  EXPECT_NEAR(blended.alpha_factor, 0.3f, 1e-6f);
  EXPECT_NEAR(sky_seen_under_leaf(back.scene), 0.5, 1e-9);
  Scene pane_alone = back.scene;  // the pane moved over the floor under the leaf's place
  pane_alone.meshes[1] = pane_alone.meshes[2];
  for (vec3& p : pane_alone.meshes[1].positions) p.x -= 3.0f;
  pane_alone.meshes.pop_back();
  // 4096 rays, each through with probability 0.7 (a hash of the ray): sd 0.0072.
  EXPECT_NEAR(sky_seen_under_leaf(pane_alone), 0.7, 0.025);
}

// ---- the CLI ---------------------------------------------------------------------------------

const std::string kRoom = test::source_dir() + "/scenes/room.toml";

// `lightbake ARGS` in `cwd` with one environment variable set (an external tool missing).
test::CliRun run_lightbake_with(const std::string& variable, const std::string& args,
                                const fs::path& cwd) {
  std::string command = "env ";
  command.append(variable).append(" '").append(LIGHTBAKE_BINARY_DIR).append("/app/lightbake' ");
  return test::run_command(command.append(args), cwd.string());
}

std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

size_t lines(const std::string& text) {
  return size_t(std::count(text.begin(), text.end(), '\n'));
}

TEST(GltfExportCli, WritesAGlbAndRefusesForeignFiles) {
  const fs::path dir = fs::path(test::output_dir()) / "gltf_export_cli";
  fs::remove_all(dir);
  fs::create_directories(dir / "out");
  const test::CliRun run =
      test::run_lightbake("export -q '" + kRoom + "' -o out/room.glb", dir.string());
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_TRUE(is_lightbake_gltf((dir / "out/room.glb").string()));
  // Its own file is replaced without --force.
  EXPECT_EQ(test::run_lightbake("export -q '" + kRoom + "' -o out/room.glb", dir.string()).status,
            0);
  // So are its Radiance and EXR lightmaps (the .hdr carried no stamp before 1 Dec 2026, and a
  // second export refused to replace it).
  const std::string both = "export -q '" + kRoom + "' -o out/both.glb --lightmap-format both";
  ASSERT_EQ(test::run_lightbake(both, dir.string()).status, 0);
  const test::CliRun again = test::run_lightbake(both, dir.string());
  EXPECT_EQ(again.status, 0) << again.err;

  // A file lightbake did not write is kept, with one line of error.
  { std::ofstream(dir / "mine.glb") << "precious"; }
  const test::CliRun refused =
      test::run_lightbake("export -q '" + kRoom + "' -o mine.glb", dir.string());
  EXPECT_NE(refused.status, 0);
  EXPECT_EQ(lines(refused.err), 1u) << refused.err;
  EXPECT_NE(refused.err.find("mine.glb"), std::string::npos) << refused.err;
  EXPECT_EQ(read_file(dir / "mine.glb"), "precious");

  // Bad arguments: one line naming the problem, nothing written.
  const test::CliRun bad_ext =
      test::run_lightbake("export -q '" + kRoom + "' -o room.obj", dir.string());
  EXPECT_NE(bad_ext.status, 0);
  EXPECT_EQ(lines(bad_ext.err), 1u) << bad_ext.err;
  EXPECT_NE(bad_ext.err.find(".glb or .gltf"), std::string::npos) << bad_ext.err;
  EXPECT_FALSE(fs::exists(dir / "room.obj"));
  const test::CliRun no_bake =
      test::run_lightbake("export -q '" + kRoom + "' missing_bake -o nb.glb", dir.string());
  EXPECT_NE(no_bake.status, 0);
  EXPECT_EQ(lines(no_bake.err), 1u) << no_bake.err;
  EXPECT_FALSE(fs::exists(dir / "nb.glb"));

  // --ktx2 without an encoder (srgb or rgbm): one line saying why, nothing written.
  for (const char* encoding : {"srgb", "rgbm"}) {
    const test::CliRun no_encoder = run_lightbake_with(
        "LIGHTBAKE_BASISU=/nonexistent/basisu",
        "export -q '" + kRoom + "' -o k.glb --ktx2 --lightmap-encoding " + encoding, dir);
    EXPECT_NE(no_encoder.status, 0);
    EXPECT_EQ(lines(no_encoder.err), 1u) << no_encoder.err;
    EXPECT_NE(no_encoder.err.find("LIGHTBAKE_BASISU"), std::string::npos) << no_encoder.err;
  }
  EXPECT_FALSE(fs::exists(dir / "k.glb"));
}

// export --denoise: Open Image Denoise from the build tree (scripts/test.sh installs pyoidn into
// build/pypi; without it this test fails). Missing, or asked for without a direct term: one
// line naming what is missing, nothing written; found: the file says the term was denoised.
TEST(GltfExport, DenoiseNeedsOpenImageDenoiseAndSaysSo) {
  const fs::path dir = fs::path(test::output_dir()) / "gltf_export_denoise";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const test::CliRun missing =
      run_lightbake_with("LIGHTBAKE_OIDN_LIB=/nonexistent/libOpenImageDenoise.so.2",
                         "export -q '" + kRoom + "' -o d.glb --contents all --denoise", dir);
  EXPECT_NE(missing.status, 0);
  EXPECT_EQ(lines(missing.err), 1u) << missing.err;
  EXPECT_NE(missing.err.find("LIGHTBAKE_OIDN_LIB"), std::string::npos) << missing.err;
  const test::CliRun indirect =
      test::run_lightbake("export -q '" + kRoom + "' -o d.glb --denoise", dir.string());
  EXPECT_NE(indirect.status, 0);
  EXPECT_EQ(lines(indirect.err), 1u) << indirect.err;
  EXPECT_TRUE(fs::is_empty(dir));

  const test::CliRun run = test::run_lightbake(
      "export -q '" + kRoom + "' -o d.glb --contents all --denoise --texel-density 10",
      dir.string());
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_NE(read_file(dir / "d.glb").find("Open Image Denoise"), std::string::npos);
}

// Re-import: the light read back from the file is the lightmap's (to half-float precision from
// the EXR, to the 8-bit encoding's precision without it); no radiosity of its own.
TEST(GltfExport, ReadBackGivesTheBakesLight) {
  const Exported& e = exported();
  const LoadResult loaded = load_scene(e.path);
  const BakeResult back = read_gltf_bake(e.path, loaded.scene);
  ASSERT_EQ(back.radiosity.meshes.size(), e.meshes.size());
  for (size_t m = 0; m < back.radiosity.meshes.size(); ++m) {
    EXPECT_TRUE(back.radiosity.meshes[m].vertex_radiance.empty()) << e.meshes[m].name;
    EXPECT_EQ(back.illumination.lightmap_uvs[m].empty(), e.meshes[m].lightmap_uvs.empty())
        << e.meshes[m].name;
  }
  EXPECT_FALSE(back.illumination.holds_direct_light);
  const Lightmap& maps = e.lightmap;
  ASSERT_EQ(back.illumination.width, maps.width);
  ASSERT_EQ(back.illumination.height, maps.height);
  for (size_t i = 0; i < maps.radiance.size(); ++i)
    for (int c = 0; c < 3; ++c)
      ASSERT_NEAR(back.illumination.radiance[i][c], maps.radiance[i][c],
                  4.9e-4f * maps.radiance[i][c] + 1e-7f);

  // Without the EXR: the PNG, within half a code step of 8-bit sRGB at the top (0.0045 scale).
  // The EXR named in the extras is beside the file: hide it to force the PNG path.
  const std::string exr = lightmap_exr_path(e.path);
  fs::rename(exr, exr + ".hidden");
  const BakeResult png = read_gltf_bake(e.path, loaded.scene);
  fs::rename(exr + ".hidden", exr);
  double worst = 0.0;
  for (size_t i = 0; i < maps.radiance.size(); ++i)
    for (int c = 0; c < 3; ++c)
      worst =
          std::max(worst, double(std::abs(png.illumination.radiance[i][c] - maps.radiance[i][c])));
  EXPECT_LE(worst, 0.0046 * e.info.map_scale);
  EXPECT_GT(worst, 0.0);  // it did read the 8-bit map
  std::printf("read back from the PNG: worst |error| %.5f of the scale\n",
              worst / e.info.map_scale);

  // A glTF lightbake did not write: refused, naming the file.
  const std::string foreign = test::source_dir() + "/tests/data/gltf/room.glb";
  try {
    read_gltf_bake(foreign, load_scene(foreign).scene);
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find(foreign), std::string::npos) << error.what();
  }
}

// Radiance HDR beside the file (--lightmap-format hdr): RGBE keeps 8 mantissa bits, so each
// channel is within 2^-8 of the texel's largest channel; read back when no EXR is there.
TEST(GltfExport, RadianceHdrBesideHoldsTheMap) {
  const Exported& e = exported();
  const std::string path = (fs::path(e.path).parent_path() / "room_hdr.glb").string();
  GltfExportOptions options;
  options.format = LightmapFormat::hdr;
  const GltfExportInfo info = export_gltf(path, e.scene, e.bake, options);
  ASSERT_EQ(info.files.size(), 2u);
  EXPECT_FALSE(fs::exists(lightmap_exr_path(path)));
  const Image hdr = read_image(lightmap_hdr_path(path));
  ASSERT_EQ(hdr.width, e.lightmap.width);
  ASSERT_EQ(hdr.height, e.lightmap.height);
  double worst = 0.0;
  for (size_t i = 0; i < e.lightmap.radiance.size(); ++i) {
    const vec3 truth = e.lightmap.radiance[i];
    const float largest = std::max({truth.x, truth.y, truth.z});
    for (int c = 0; c < 3; ++c)
      if (largest > 0.0f)
        worst = std::max(
            worst, double(std::abs(hdr.pixels[i * size_t(hdr.channels) + size_t(c)] - truth[c])) /
                       largest);
  }
  EXPECT_LE(worst, 1.0 / 128.0);  // measured below 2^-8
  std::printf("Radiance HDR: worst |error| %.3g of the texel's largest channel\n", worst);
  const BakeResult back = read_gltf_bake(path, load_scene(path).scene);
  ASSERT_EQ(back.illumination.radiance.size(), e.lightmap.radiance.size());
  EXPECT_EQ(back.illumination.radiance[e.lightmap.radiance.size() / 2][0],
            hdr.pixels[e.lightmap.radiance.size() / 2 * size_t(hdr.channels)]);
}

// A cancelled export (the lightmap's progress says stop) throws Cancelled and writes nothing.
TEST(GltfExport, CancelledWritesNothing) {
  const Exported& e = exported();
  const std::string path = (fs::path(e.path).parent_path() / "cancelled.glb").string();
  std::atomic<bool> stop{true};
  Progress progress;
  progress.cancel = &stop;
  GltfExportOptions options;
  options.contents = LightmapContents::all;
  EXPECT_THROW(export_gltf(path, e.scene, e.bake, options, progress), Cancelled);
  EXPECT_FALSE(fs::exists(path));
  EXPECT_FALSE(fs::exists(lightmap_exr_path(path)));
  for (const auto& entry : fs::directory_iterator(fs::path(path).parent_path()))
    EXPECT_EQ(entry.path().filename().string().find(".tmp-"), std::string::npos)
        << entry.path();  // no temporary left either
}

// Bad input: one line naming the file, a non-zero status, nothing written.
// Lamps leave as KHR_lights_punctual (cd and lx at 683 lm/W, a node turning -Z to the light's
// direction) and come back through our loader as they went out.
TEST(GltfExportCli, LampsRoundTripAsKhrLightsPunctual) {
  const fs::path dir = test::fresh_dir("gltf_export", "lamps");
  const std::string scene = test::source_dir() + "/scenes/lamps.toml";
  const test::CliRun run =
      test::run_lightbake("export -q --quality draft '" + scene + "' -o lamps.glb", dir.string());
  ASSERT_EQ(run.status, 0) << run.err;
  const LoadResult original = load_scene(scene);
  const LoadResult exported = load_scene((dir / "lamps.glb").string());
  ASSERT_EQ(original.scene.lights.size(), 3u);
  ASSERT_EQ(exported.scene.lights.size(), original.scene.lights.size());
  for (size_t i = 0; i < original.scene.lights.size(); ++i) {
    const Lamp& a = original.scene.lights[i];
    const Lamp& b = exported.scene.lights[i];
    SCOPED_TRACE(a.name);
    EXPECT_EQ(b.name, a.name);
    EXPECT_EQ(b.kind, a.kind);
    EXPECT_LT(glm::length(b.position - a.position), 1e-5f);
    EXPECT_LT(glm::length(b.direction - a.direction), 1e-5f);
    EXPECT_LT(glm::length(b.intensity - a.intensity), 1e-5f * glm::length(a.intensity));
    EXPECT_NEAR(b.inner_cone, a.inner_cone, 1e-6f);
    EXPECT_NEAR(b.outer_cone, a.outer_cone, 1e-6f);
    EXPECT_EQ(b.range, a.range);
  }
}

TEST(GltfExportCli, BadInputIsOneLineNamingTheFileAndWritesNothing) {
  const fs::path dir = fs::path(test::output_dir()) / "gltf_export_bad";
  fs::remove_all(dir);
  fs::create_directories(dir);
  ASSERT_EQ(test::run_lightbake("bake -q '" + kRoom + "' -o room_bake", dir.string()).status, 0);
  const std::string other = test::source_dir() + "/scenes/cornell_box.toml";
  ASSERT_EQ(test::run_lightbake("bake -q '" + other + "' -o other_bake", dir.string()).status, 0);
  auto copy = [&](const std::string& name) {
    fs::copy(dir / "room_bake", dir / name, fs::copy_options::recursive);
    return dir / name;
  };
  fs::remove(copy("no_radiosity") / "radiosity.bin");
  fs::remove(copy("no_exr") / "illumination.exr");
  {
    const fs::path bin = copy("corrupt") / "illumination.bin";
    const std::string bytes = read_file(bin);
    std::ofstream(bin, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  }
  struct Case {
    std::string args, names;
  };
  const std::vector<Case> cases = {
      {"other_bake -o a.glb", "other_bake/manifest.json"},
      {"no_radiosity -o b.glb", "no_radiosity/radiosity.bin"},
      {"no_exr -o c.glb", "no_exr/illumination.exr"},
      {"corrupt -o d.glb", "corrupt/illumination.bin"},
      {"room_bake -o missing/folder/e.glb", "missing/folder"},
      // Fewer shadow rays serve the direct term of --contents all, plain maps only.
      {"room_bake -o f.glb --shadow-rays 4", "--shadow-rays"},
      {"room_bake -o g.glb --contents all --directional --shadow-rays 4", "--shadow-rays"},
      // The share is the directional maps'.
      {"room_bake -o i.glb --contents all --directional-share", "--directional-share"},
  };
  for (const Case& c : cases) {
    const test::CliRun run =
        test::run_lightbake("export -q '" + kRoom + "' " + c.args, dir.string());
    EXPECT_NE(run.status, 0) << c.args;
    EXPECT_EQ(lines(run.err), 1u) << c.args << ": " << run.err;
    EXPECT_NE(run.err.find(c.names), std::string::npos) << c.args << ": " << run.err;
  }
  for (const char* name : {"a", "b", "c", "d", "f", "g", "i"}) {
    EXPECT_FALSE(fs::exists(dir / (std::string(name) + ".glb"))) << name;
    EXPECT_FALSE(fs::exists(dir / (std::string(name) + ".lightmap.exr"))) << name;
  }
  EXPECT_FALSE(fs::exists(dir / "missing"));
}

// Round trip: the snapshot of the exported file (its lightmap as the baked light) against the
// snapshot of the scene with its bake (vertex radiosity + caustic map), same camera. Shadow
// maps off (--no-shadows) so that both draw the same direct light and the difference is the
// baked light alone: the texel resampling of the radiosity (a texel of 2.5 cm against the
// vertex interpolation) and the glass ball's rim, which refracts the room at grazing angles.
TEST(GltfExportCli, SnapshotOfTheFileMatchesSnapshotOfTheBake) {
  const fs::path dir = fs::path(test::output_dir()) / "gltf_export_snapshot";
  fs::remove_all(dir);
  fs::create_directories(dir);
  ASSERT_EQ(test::run_lightbake("bake -q '" + kRoom + "' -o bake", dir.string()).status, 0);
  ASSERT_EQ(test::run_lightbake("export -q '" + kRoom + "' bake -o room.glb", dir.string()).status,
            0);
  ASSERT_EQ(
      test::run_lightbake("snapshot -q --no-shadows '" + kRoom + "' bake -o orig.exr", dir.string())
          .status,
      0);
  const test::CliRun back =
      test::run_lightbake("snapshot -q --no-shadows room.glb -o back.exr", dir.string());
  ASSERT_EQ(back.status, 0) << back.err;
  EXPECT_EQ(back.err.find("baking"), std::string::npos) << "read the file's light, no new bake";
  EXPECT_EQ(back.err.find("warning"), std::string::npos) << back.err;
  const Image orig = read_image((dir / "orig.exr").string());
  const ImageDifference d = compare_images(read_image((dir / "back.exr").string()), orig);
  // Measured: mean relative error 0.0074 (compare_images; `lightbake compare` says MRE 0.0016,
  // sum ratio 1.0005).
  std::printf("snapshot of room.glb vs of the bake: mean relative %.3g, rmse %.3g W/(sr m^2)\n",
              d.mean_relative, d.rmse);
  EXPECT_LT(d.mean_relative, 0.015);
  RecordProperty("mean_relative", std::to_string(d.mean_relative));

  // --contents all: the file carries the direct light (soft shadows, HQ's estimator) and the
  // re-imported scene adds none of its own; against the bake with its shadow maps. Were the
  // direct light added twice, the image would be about twice as bright.
  ASSERT_EQ(
      test::run_lightbake("export -q --contents all '" + kRoom + "' bake -o all.glb", dir.string())
          .status,
      0);
  ASSERT_EQ(
      test::run_lightbake("snapshot -q '" + kRoom + "' bake -o orig_shadows.exr", dir.string())
          .status,
      0);
  ASSERT_EQ(test::run_lightbake("snapshot -q all.glb -o all.exr", dir.string()).status, 0);
  const Image shadows = read_image((dir / "orig_shadows.exr").string());
  const Image all = read_image((dir / "all.exr").string());
  const ImageDifference a = compare_images(all, shadows);
  double sum_all = 0.0, sum_orig = 0.0;
  for (size_t i = 0; i < all.pixels.size(); ++i)
    sum_all += all.pixels[i], sum_orig += shadows.pixels[i];
  // Measured: mean relative error 0.0157 (penumbrae: shadow maps against soft shadows),
  // sum ratio 0.9988.
  std::printf("contents all: mean relative %.3g, sum ratio %.4f\n", a.mean_relative,
              sum_all / sum_orig);
  EXPECT_LT(a.mean_relative, 0.03);
  EXPECT_NEAR(sum_all / sum_orig, 1.0, 0.01);

  // The window shows the same: `view room.glb` reads the file's light too (a new bake would
  // differ by its noise). As in tests/viewer: within 1.5/255 per channel under Xvfb.
  if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "xvfb-run is not installed (Debian package xvfb)";
  // The window draws pixel centres: the snapshot too (its default averages 2 x 2 sub-pixels).
  ASSERT_EQ(test::run_lightbake("snapshot -q room.glb --size 320x240 --pixel-samples 1 -o snap.png",
                                dir.string())
                .status,
            0);
  const std::string view = "cd '" + dir.string() + "' && " +
                           test::xvfb_lightbake_command(
                               "view room.glb --size 320x240 --hide-panel --frames 3 "
                               "--screenshot window.png > /dev/null 2>&1");
  ASSERT_EQ(std::system(view.c_str()), 0) << view;
  const ImageDifference w = compare_images(read_image((dir / "window.png").string()),
                                           read_image((dir / "snap.png").string()), 1.5f / 255.0f);
  EXPECT_EQ(w.fraction_over, 0.0) << "largest " << w.max_abs * 255.0 << "/255";
}

}  // namespace
}  // namespace lb
