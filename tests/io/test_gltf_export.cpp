// The glTF export (bake/io/gltf_export.h, docs/export.md): a small baked room with a mirror
// and a ball (so it has a caustic map) is written, read back with tinygltf and with our own
// loader, and every exported quantity is compared with the bake; the CLI's file safety.

#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <glm/gtc/constants.hpp>

#include "bake/io/gltf_bake_read.h"
#include "bake/io/gltf_export.h"
#include "bake/io/scene_load.h"
#include "bake/pipeline/bake.h"
#include "scenes.h"
#include "test_helpers.h"

namespace lb {
namespace {

namespace fs = std::filesystem;

struct Exported {
  Scene scene;
  BakeResult bake;
  BakedScene baked;
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
    e->baked = make_baked_scene(e->scene, e->bake);
    const fs::path dir = fs::path(test::output_dir()) / "gltf_export";
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
  ASSERT_GT(e.bake.illumination.width, 0) << "the mirror must cast a caustic map";
  const size_t meshes = e.baked.scene.meshes.size();
  ASSERT_EQ(e.model.meshes.size(), meshes);  // every mesh of the room is non-empty
  EXPECT_EQ(e.info.meshes, meshes);
  size_t with_colour = 0, with_map = 0;
  for (size_t m = 0; m < meshes; ++m) {
    const Mesh& mesh = e.baked.scene.meshes[m];
    ASSERT_EQ(e.model.meshes[m].primitives.size(), 1u);
    const tinygltf::Primitive& p = e.model.meshes[m].primitives[0];
    const size_t n = mesh.positions.size();
    EXPECT_EQ(e.model.accessors[size_t(p.attributes.at("POSITION"))].count, n) << mesh.name;
    EXPECT_TRUE(
        test::same_bits(accessor_data<vec3>(e.model, p.attributes.at("POSITION")), mesh.positions))
        << mesh.name;
    const auto indices = accessor_data<uint32_t>(e.model, p.indices);
    ASSERT_EQ(indices.size(), mesh.triangles.size() * 3) << mesh.name;
    EXPECT_EQ(std::memcmp(indices.data(), mesh.triangles.data(), indices.size() * 4), 0)
        << mesh.name;
    // COLOR_0 is the bake's vertex radiance, bit for bit.
    const std::vector<vec3>& radiance = e.baked.vertex_radiance[m];
    if (!radiance.empty()) {
      ASSERT_TRUE(p.attributes.count("COLOR_0")) << mesh.name;
      // Stored divided by a power of two, so that glTF's [0, 1] holds: undone exactly.
      std::vector<vec3> colour = accessor_data<vec3>(e.model, p.attributes.at("COLOR_0"));
      for (vec3& c : colour) {
        ASSERT_LE(std::max({c.x, c.y, c.z}), 1.0f);
        ASSERT_GE(std::min({c.x, c.y, c.z}), 0.0f);
        c *= e.info.color_scale;
      }
      EXPECT_TRUE(test::same_bits(colour, radiance)) << mesh.name;
      ++with_colour;
    } else {
      EXPECT_FALSE(p.attributes.count("COLOR_0")) << mesh.name;
    }
    // TEXCOORD_1 is the lightmap UVs (of the split or refined mesh), bit for bit.
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
  // The diffuse walls and ball carry radiosity; the mirror does not.
  EXPECT_EQ(with_colour, e.info.radiosity_meshes);
  EXPECT_GE(with_colour, meshes - 1);
  EXPECT_GE(with_map, 1u);
  EXPECT_EQ(e.model.cameras.size(), e.scene.cameras.size());
  // The scale is a power of two, recorded for consumers, and the largest colour is in (0.5, 1].
  EXPECT_EQ(std::exp2(std::round(std::log2(e.info.color_scale))), e.info.color_scale);
  EXPECT_EQ(e.model.asset.extras.Get("lightbake_color_0_scale").GetNumberAsDouble(),
            double(e.info.color_scale));
  float largest = 0.0f;
  for (const auto& mesh : e.baked.vertex_radiance)
    for (const vec3& r : mesh) largest = std::max({largest, r.x, r.y, r.z});
  EXPECT_GT(largest / e.info.color_scale, 0.5f);
  EXPECT_LE(largest / e.info.color_scale, 1.0f);
  for (const tinygltf::Camera& camera : e.model.cameras)
    EXPECT_GT(camera.perspective.zfar, camera.perspective.znear);  // finite: the validator
}

TEST(GltfExport, LightmapPngDecodesWithinItsStatedPrecision) {
  const Exported& e = exported();
  const IlluminationMaps& maps = e.bake.illumination;
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
  }
  EXPECT_EQ(bound, e.info.lightmapped_meshes);
  EXPECT_GE(bound, 1u);
}

TEST(GltfExport, ExrBesideHoldsTheMapInHalfFloat) {
  const Exported& e = exported();
  const Image exr = read_image(lightmap_exr_path(e.path));
  ASSERT_EQ(exr.width, e.bake.illumination.width);
  ASSERT_EQ(exr.height, e.bake.illumination.height);
  ASSERT_EQ(exr.channels, 3);
  // Half floats: 11 significant bits, relative error <= 2^-11 = 4.9e-4 (normal range).
  for (size_t i = 0; i < e.bake.illumination.radiance.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const float truth = e.bake.illumination.radiance[i][c];
      ASSERT_NEAR(exr.pixels[i * 3 + size_t(c)], truth, 4.9e-4f * truth + 1e-7f) << i;
    }
}

TEST(GltfExport, ReloadsThroughOurLoaderWithTheSameSurface) {
  const Exported& e = exported();
  const LoadResult loaded = load_scene(e.path);
  EXPECT_EQ(triangle_count(loaded.scene), triangle_count(e.baked.scene));
  ASSERT_EQ(loaded.scene.meshes.size(), e.baked.scene.meshes.size());
  for (size_t m = 0; m < loaded.scene.meshes.size(); ++m) {
    const Material& original = e.scene.materials[size_t(e.baked.scene.meshes[m].material)];
    const Material& back = loaded.scene.materials[size_t(loaded.scene.meshes[m].material)];
    EXPECT_EQ(back.kind, original.kind) << e.baked.scene.meshes[m].name;
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(back.reflectance[c], original.reflectance[c], 1e-6f);
      EXPECT_NEAR(back.emission[c], original.emission[c], 1e-5f * original.emission[c]);
    }
    // TEXCOORD_1 comes back as the lightmap UVs.
    EXPECT_TRUE(
        test::same_bits(loaded.scene.meshes[m].lightmap_uvs, e.baked.scene.meshes[m].lightmap_uvs));
  }
  EXPECT_EQ(loaded.scene.cameras.size(), e.scene.cameras.size());
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
    if (a.reflectance_texture < 0 || b.reflectance_texture < 0) continue;
    const Texture& ta = original.scene.textures[size_t(a.reflectance_texture)];
    const Texture& tb = back.scene.textures[size_t(b.reflectance_texture)];
    ASSERT_EQ(tb.width, ta.width);
    ASSERT_EQ(tb.height, ta.height);
    ASSERT_EQ(tb.texels.size(), ta.texels.size());
    float worst = 0.0f;  // 8-bit sRGB in, 8-bit sRGB out: the same bytes, the same floats
    for (size_t t = 0; t < ta.texels.size(); ++t)
      worst = std::max(worst, std::abs(ta.texels[t] - tb.texels[t]));
    EXPECT_LE(worst, 1e-6f);
  }
  EXPECT_EQ(triangle_count(back.scene),
            triangle_count(make_baked_scene(original.scene, bake).scene));
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
}

// ---- the CLI ---------------------------------------------------------------------------------

const std::string kRoom = test::source_dir() + "/scenes/room.toml";

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
  fs::create_directories(dir);
  const test::CliRun run =
      test::run_lightbake("export -q '" + kRoom + "' -o out/room.glb", dir.string());
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_TRUE(is_lightbake_gltf((dir / "out/room.glb").string()));
  // Its own file is replaced without --force.
  EXPECT_EQ(test::run_lightbake("export -q '" + kRoom + "' -o out/room.glb", dir.string()).status,
            0);

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
}

// Re-import: the light read back from the file is the bake's (COLOR_0 exactly; the map to
// half-float precision from the EXR, to the 8-bit encoding's precision without it).
TEST(GltfExport, ReadBackGivesTheBakesLight) {
  const Exported& e = exported();
  const LoadResult loaded = load_scene(e.path);
  const BakeResult back = read_gltf_bake(e.path, loaded.scene);
  ASSERT_EQ(back.radiosity.meshes.size(), e.baked.vertex_radiance.size());
  for (size_t m = 0; m < back.radiosity.meshes.size(); ++m) {
    EXPECT_TRUE(
        test::same_bits(back.radiosity.meshes[m].vertex_radiance, e.baked.vertex_radiance[m]))
        << e.baked.scene.meshes[m].name;
    EXPECT_EQ(back.illumination.lightmap_uvs[m].empty(),
              e.baked.scene.meshes[m].lightmap_uvs.empty())
        << e.baked.scene.meshes[m].name;
  }
  const IlluminationMaps& maps = e.bake.illumination;
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

TEST(GltfExportCli, SnapshotOfTheFileMatchesSnapshotOfTheBake) {
  const fs::path dir = fs::path(test::output_dir()) / "gltf_export_snapshot";
  fs::remove_all(dir);
  fs::create_directories(dir);
  ASSERT_EQ(test::run_lightbake("bake -q '" + kRoom + "' -o bake", dir.string()).status, 0);
  ASSERT_EQ(test::run_lightbake("export -q '" + kRoom + "' bake -o room.glb", dir.string()).status,
            0);
  ASSERT_EQ(
      test::run_lightbake("snapshot -q '" + kRoom + "' bake -o orig.exr", dir.string()).status, 0);
  const test::CliRun back = test::run_lightbake("snapshot -q room.glb -o back.exr", dir.string());
  ASSERT_EQ(back.status, 0) << back.err;
  EXPECT_EQ(back.err.find("baking"), std::string::npos) << "read the file's light, no new bake";
  const ImageDifference d = compare_images(read_image((dir / "back.exr").string()),
                                           read_image((dir / "orig.exr").string()));
  // Measured: mean relative error 6.3e-6 (the map's half-float rounding).
  std::printf("snapshot of room.glb vs of the bake: mean relative %.3g, rmse %.3g W/(sr m^2)\n",
              d.mean_relative, d.rmse);
  EXPECT_LT(d.mean_relative, 1e-4);
  RecordProperty("mean_relative", std::to_string(d.mean_relative));

  // The window shows the same: `view room.glb` reads the file's light too (a new bake would
  // differ by its noise). As in tests/viewer: within 1.5/255 per channel under Xvfb.
  if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "xvfb-run is not installed (Debian package xvfb)";
  ASSERT_EQ(
      test::run_lightbake("snapshot -q room.glb --size 320x240 -o snap.png", dir.string()).status,
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
