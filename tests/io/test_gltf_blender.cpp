// Blender 4 style glTF (issue 14): KHR_animation_pointer, lamps, KHR_texture_transform and
// MikkTSpace tangents for a normal map, on files the test writes itself
// (blender_style_gltf.cpp): what loads, what is warned, and that it renders as it should.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <glm/gtc/constants.hpp>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>

#include "bake/accel.h"
#include "bake/io/image_io.h"
#include "bake/io/scene_load.h"
#include "bake/io/uv_transform.h"
#include "bake/light_sources.h"
#include "bake/lights.h"
#include "bake/surface.h"
#include "blender_style_gltf.h"
#include "test_helpers.h"

namespace lb {
namespace {

namespace fs = std::filesystem;

std::string all_warnings(const LoadResult& result) {
  std::string text;
  for (const std::string& warning : result.warnings) text += warning + "\n";
  return text;
}

const Mesh& mesh_named(const Scene& scene, const std::string& name) {
  for (const Mesh& mesh : scene.meshes)
    if (mesh.name == name) return mesh;
  throw std::runtime_error("no mesh " + name);
}

// ---- KHR_texture_transform ------------------------------------------------------------------

TEST(TextureTransform, SpecExampleSamplesTheLowerLeftQuadrant) {
  // The extension's example: offset (0, 1), rotation pi/2, scale 0.5 "utilizes only the lower
  // left quadrant of the source image, rotated clockwise 90 degrees". With v down the image,
  // the lower left quadrant is u in [0, 0.5], v in [0.5, 1].
  const glm::dmat3 m = uv_transform_matrix({0, 1}, glm::half_pi<double>(), {0.5, 0.5});
  const vec2 corners[4][2] = {{{0, 0}, {0, 1}},  // uv -> uv'
                              {{1, 0}, {0, 0.5f}},
                              {{1, 1}, {0.5f, 0.5f}},
                              {{0, 1}, {0.5f, 1}}};
  for (const auto& [uv, expected] : corners) {
    const vec2 result = apply_uv_transform(m, uv);
    EXPECT_NEAR(result.x, expected.x, 1e-7f) << uv.x << ", " << uv.y;
    EXPECT_NEAR(result.y, expected.y, 1e-7f) << uv.x << ", " << uv.y;
  }
}

// By hand, term by term, as the extension states: scale, then rotate (u' = cos u + sin v,
// v' = -sin u + cos v), then offset.
vec2 transformed_by_hand(vec2 uv) {
  const double su = uv.x * test::kFloorUvScale[0], sv = uv.y * test::kFloorUvScale[1];
  const double c = std::cos(test::kFloorUvRotation), s = std::sin(test::kFloorUvRotation);
  return vec2(float(c * su + s * sv + test::kFloorUvOffset[0]),
              float(-s * su + c * sv + test::kFloorUvOffset[1]));
}

TEST(TextureTransform, TransformedTextureSamplesLikeUvsTransformedByHand) {
  const fs::path dir = test::fresh_dir("gltf_blender", "texture_transform");
  const std::vector<vec2> uvs = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
  std::vector<vec2> by_hand;
  for (vec2 uv : uvs) by_hand.push_back(transformed_by_hand(uv));
  const std::string transform =
      R"({"KHR_texture_transform": {"offset": [0.1, 0.2], "rotation": 0.4, "scale": [2, 2]}})";
  const std::string with_texcoord_1 = R"({"KHR_texture_transform": {"offset": [0.1, 0.2],
      "rotation": 0.4, "scale": [2, 2], "texCoord": 1}})";
  const std::vector<vec2> zeros(4, vec2(0.0f));
  const LoadResult transformed =
      load_scene(test::write_textured_quad_gltf(dir.string(), "transformed", uvs, {}, transform));
  const LoadResult hand =
      load_scene(test::write_textured_quad_gltf(dir.string(), "by_hand", by_hand, {}, "{}"));
  // The extension's texCoord overrides the textureInfo's: TEXCOORD_1 holds the UVs here.
  const LoadResult override_set = load_scene(
      test::write_textured_quad_gltf(dir.string(), "texcoord1", zeros, uvs, with_texcoord_1));
  for (const LoadResult* result : {&transformed, &hand, &override_set}) {
    // Only the scene-level note that nothing emits: the transform and texCoord are honoured.
    EXPECT_EQ(result->warnings.size(), 1u) << all_warnings(*result);
    EXPECT_EQ(all_warnings(*result).find("nothing emits light"),
              result->scene.source_path.size() + 2)
        << all_warnings(*result);
    ASSERT_EQ(result->scene.meshes.size(), 1u);
  }
  const Scene& a = transformed.scene;
  const Scene& b = hand.scene;
  ASSERT_GE(a.materials[0].reflectance_texture, 0);
  const Texture& texture = a.textures[size_t(a.materials[0].reflectance_texture)];
  float max_uv_difference = 0.0f, max_sample_difference = 0.0f;
  for (const Scene* other : {&b, &override_set.scene})
    for (size_t v = 0; v < 4; ++v)
      max_uv_difference =
          std::max(max_uv_difference, glm::length(a.meshes[0].uvs[v] - other->meshes[0].uvs[v]));
  // The texture seen at points across the quad (barycentric grid over both triangles).
  for (size_t t = 0; t < 2; ++t)
    for (int i = 0; i <= 8; ++i)
      for (int j = 0; i + j <= 8; ++j) {
        auto uv_at = [&](const Mesh& mesh) {
          const uvec3 tri = mesh.triangles[t];
          const float bu = float(i) / 8, bv = float(j) / 8;
          return mesh.uvs[tri.x] * (1 - bu - bv) + mesh.uvs[tri.y] * bu + mesh.uvs[tri.z] * bv;
        };
        const vec4 sa = sample_texture(texture, uv_at(a.meshes[0]));
        const vec4 sb = sample_texture(texture, uv_at(b.meshes[0]));
        max_sample_difference = std::max(max_sample_difference, glm::length(sa - sb));
      }
  EXPECT_LT(max_uv_difference, 1e-6f);
  EXPECT_LT(max_sample_difference, 1e-5f);
  // And the transform did something: the checker is not sampled where the raw UVs point.
  EXPECT_GT(glm::length(a.meshes[0].uvs[1] - uvs[1]), 1.0f);
}

// ---- A Blender 4 style export ---------------------------------------------------------------

TEST(BlenderStyleGltf, LoadsWithOneWarningPerSkippedKind) {
  const fs::path dir = test::fresh_dir("gltf_blender", "loads");
  const std::string path = test::write_blender_style_gltf(dir.string(), "lamps", {});
  const LoadResult result = load_scene(path);
  // Exactly one warning: the animation (KHR_animation_pointer, which tinygltf alone refuses).
  // The lamps are lights now.
  ASSERT_EQ(result.warnings.size(), 1u) << all_warnings(result);
  EXPECT_EQ(result.warnings[0],
            path +
                ": at animations: 1 animation(s) ignored; the scene is loaded at rest "
                "(KHR_animation_pointer included)");
  const Scene& scene = result.scene;
  ASSERT_EQ(scene.meshes.size(), 2u);
  ASSERT_EQ(scene.cameras.size(), 1u);
  const Mesh& floor = mesh_named(scene, "Floor");
  const Material& floor_material = scene.materials[size_t(floor.material)];
  EXPECT_EQ(floor_material.bump, BumpKind::normal_map);
  EXPECT_GE(floor_material.reflectance_texture, 0);
  EXPECT_EQ(floor.tangents.size(), floor.positions.size());  // generated (MikkTSpace)
  // Texture coordinates carry the transform: vertex 0 had uv (0, 0), vertex 4 uv (1, 0).
  for (size_t v : {size_t(0), size_t(4), size_t(24)}) {
    const vec2 raw(float(v % 5) / 4, float(v / 5) / 4);
    const vec2 expected = transformed_by_hand(raw);
    EXPECT_NEAR(floor.uvs[v].x, expected.x, 1e-6f) << v;
    EXPECT_NEAR(floor.uvs[v].y, expected.y, 1e-6f) << v;
  }
  EXPECT_TRUE(scene.materials[size_t(mesh_named(scene, "Panel").material)].is_emitter());
  // The lamps at their nodes, shining down their local -Z, in W/sr at 683 lm/W.
  ASSERT_EQ(scene.lights.size(), 2u);
  const Lamp& point = scene.lights[0];
  EXPECT_EQ(point.name, "Lamp");
  EXPECT_EQ(point.kind, LampKind::point);
  EXPECT_NEAR(glm::length(point.position - vec3(-0.5f, 1.5f, 0.5f)), 0.0f, 1e-6f);
  EXPECT_NEAR(point.intensity.x, 54.35 / 683.0, 1e-7);
  const Lamp& spot = scene.lights[1];
  EXPECT_EQ(spot.kind, LampKind::spot);
  EXPECT_NEAR(glm::length(spot.direction - vec3(0.0f, -1.0f, 0.0f)), 0.0f,
              1e-6f);  // -90 deg about x
  EXPECT_FLOAT_EQ(spot.inner_cone, 0.3f);
  EXPECT_FLOAT_EQ(spot.outer_cone, 0.6f);
  EXPECT_NEAR(spot.intensity.y, 100.0 / 683.0, 1e-7);
}

TEST(BlenderStyleGltf, GlbWithAnAnimationPointerLoadsToo) {
  // The .glb path rebuilds the binary container around the JSON without its animations.
  const fs::path dir = test::fresh_dir("gltf_blender", "glb");
  const std::string gltf = test::write_blender_style_gltf(dir.string(), "lamps", {});
  const LoadResult from_gltf = load_scene(gltf);
  // A .glb with the same JSON and the .bin as its BIN chunk.
  std::ifstream json_in(gltf), bin_in(dir / "lamps.bin", std::ios::binary);
  nlohmann::json document = nlohmann::json::parse(json_in);
  std::string bin((std::istreambuf_iterator<char>(bin_in)), std::istreambuf_iterator<char>());
  document["buffers"][0].erase("uri");
  std::string json_text = document.dump();
  while (json_text.size() % 4) json_text += ' ';
  while (bin.size() % 4) bin += '\0';
  auto u32 = [](size_t v) {
    const uint32_t x = uint32_t(v);
    return std::string(reinterpret_cast<const char*>(&x), 4);
  };
  const std::string glb = "glTF" + u32(2) + u32(12 + 8 + json_text.size() + 8 + bin.size()) +
                          u32(json_text.size()) + "JSON" + json_text + u32(bin.size()) +
                          std::string("BIN\0", 4) + bin;
  const std::string glb_path = (dir / "lamps.glb").string();
  std::ofstream(glb_path, std::ios::binary) << glb;
  const LoadResult from_glb = load_scene(glb_path);
  ASSERT_EQ(from_glb.warnings.size(), 1u) << all_warnings(from_glb);
  EXPECT_EQ(from_glb.scene.lights.size(), 2u);
  EXPECT_NE(from_glb.warnings[0].find("1 animation(s) ignored"), std::string::npos);
  ASSERT_EQ(from_glb.scene.meshes.size(), from_gltf.scene.meshes.size());
  for (size_t m = 0; m < from_glb.scene.meshes.size(); ++m) {
    EXPECT_TRUE(
        test::same_bits(from_glb.scene.meshes[m].positions, from_gltf.scene.meshes[m].positions));
    EXPECT_TRUE(
        test::same_bits(from_glb.scene.meshes[m].tangents, from_gltf.scene.meshes[m].tangents));
  }
}

TEST(BlenderStyleGltf, SkinsMorphTargetsAndUnknownExtensionsWarnOnceEach) {
  const fs::path dir = test::fresh_dir("gltf_blender", "once_each");
  const std::string source = test::write_blender_style_gltf(dir.string(), "lamps", {});
  std::ifstream in(source);
  nlohmann::json document = nlohmann::json::parse(in);
  in.close();
  // Both meshes skinned and morphed; an unknown extension on both primitives (where the loader
  // does not look itself) and one at the top level; KHR_animation_pointer required.
  document["skins"] = {{{"joints", {0}}}};
  for (int node : {0, 1}) document["nodes"][node]["skin"] = 0;
  for (int mesh : {0, 1}) {
    auto& primitive = document["meshes"][mesh]["primitives"][0];
    primitive["targets"] = {{{"POSITION", primitive["attributes"]["POSITION"]}}};
    primitive["extensions"] = {{"EXT_made_up_primitive", nlohmann::json::object()}};
  }
  document["extensions"]["EXT_made_up_top"] = nlohmann::json::object();
  document["extensionsRequired"] = {"KHR_animation_pointer"};
  // The normal texture untransformed while the base colour is: one UV set per mesh.
  document["materials"][0]["normalTexture"].erase("extensions");
  const std::string path = (dir / "once_each.gltf").string();
  std::ofstream(path) << document.dump();
  const LoadResult result = load_scene(path);
  const std::string warnings = all_warnings(result);
  for (const std::string expected :
       {": at extensionsRequired[0]: required extension KHR_animation_pointer is not "
        "supported; ignored",
        ": at animations: 1 animation(s) ignored",
        ": at nodes[0].skin: skins on 2 node(s) ignored; bind pose used",
        ": at meshes[0].primitives[0].targets: morph targets on 2 primitive(s) ignored; base "
        "shape used",
        ": at extensions.EXT_made_up_top: unsupported extension ignored",
        ": at meshes[0].primitives[0].extensions.EXT_made_up_primitive: unsupported extension "
        "ignored",
        ": at materials[0].normalTexture: UV set or KHR_texture_transform differs from "
        "baseColorTexture's; a mesh has one UV set, so that one is used"}) {
    EXPECT_NE(warnings.find(path + expected), std::string::npos) << expected << "\n" << warnings;
  }
  EXPECT_EQ(result.warnings.size(), 7u) << warnings;
  EXPECT_EQ(result.scene.meshes.size(), 2u);
  // An unknown extension that is required stays a one-line error.
  document["extensionsRequired"] = {"EXT_made_up_primitive"};
  std::ofstream(path) << document.dump();
  try {
    load_scene(path);
    ADD_FAILURE() << "loaded";
  } catch (const SceneError& e) {
    EXPECT_EQ(std::string(e.what()),
              path +
                  ": at extensionsRequired[0]: required extension EXT_made_up_primitive is "
                  "not supported (the data cannot be read without it)");
  }
}

// Direct light only (no bake): the normal map's shading, through the viewer's renderer.
Image direct_snapshot(const fs::path& dir, const std::string& file, const std::string& out) {
  const test::CliRun run = test::run_lightbake(
      "snapshot -q --no-bake --terms direct --size 160x120 " + file + " -o " + out, dir.string());
  EXPECT_EQ(run.status, 0) << run.err;
  return read_image((dir / out).string());
}

double max_channel(const Image& image) {
  double best = 0.0;
  for (float v : image.pixels) best = std::max(best, double(v));
  return best;
}

TEST(BlenderStyleGltf, RendersNonBlackAndItsNormalMapShadesLikeExplicitMikkTSpaceTangents) {
  const fs::path dir = test::fresh_dir("gltf_blender", "render");
  test::write_blender_style_gltf(dir.string(), "generated", {});
  test::write_blender_style_gltf(dir.string(), "explicit", {.explicit_tangents = true});
  test::write_blender_style_gltf(dir.string(), "wrong_w",
                                 {.explicit_tangents = true, .negate_tangent_w = true});
  const Image generated = direct_snapshot(dir, "generated.gltf", "generated.exr");
  const Image explicit_tangents = direct_snapshot(dir, "explicit.gltf", "explicit.exr");
  const Image wrong_w = direct_snapshot(dir, "wrong_w.gltf", "wrong_w.exr");
  ASSERT_FALSE(generated.pixels.empty());
  ASSERT_EQ(generated.pixels.size(), explicit_tangents.pixels.size());
  const double peak = max_channel(generated);
  EXPECT_GT(peak, 0.1) << "lit by the emissive panel, not black";
  const ImageDifference same = compare_images(generated, explicit_tangents, 0.01f);
  const ImageDifference flipped = compare_images(generated, wrong_w, 0.01f);
  std::printf(
      "peak %.4f W/(sr m^2); generated vs explicit tangents: max |d| %.6f; vs negated w: "
      "max |d| %.4f, %.3f of the pixels over 0.01\n",
      peak, same.max_abs, flipped.max_abs, flipped.fraction_over);
  EXPECT_LT(same.max_abs, 1e-3 * peak);
  // The whole pipeline: bake (radiosity from the panel), then the snapshot of every term.
  const test::CliRun baked =
      test::run_lightbake("snapshot -q --size 160x120 generated.gltf -o baked.exr", dir.string());
  ASSERT_EQ(baked.status, 0) << baked.err;
  const double baked_peak = max_channel(read_image((dir / "baked.exr").string()));
  std::printf("baked snapshot peak %.4f W/(sr m^2)\n", baked_peak);
  EXPECT_GT(baked_peak, 0.1);
  EXPECT_GT(flipped.max_abs, 0.05 * peak) << "the test can see a wrong tangent frame";
}

// Blender's exporter in its default (Standard) lighting mode writes a lamp of P W as P/(4 pi) *
// 683 cd: 54.35 cd is a 1 W point lamp, radiant intensity 1/(4 pi) W/sr.
TEST(BlenderStyleGltf, InfoListsTheLampsWithTheirPower) {
  const fs::path dir = test::fresh_dir("gltf_blender", "info");
  test::write_blender_style_gltf(dir.string(), "lamps", {});
  const test::CliRun run = test::run_lightbake("info lamps.gltf", dir.string());
  EXPECT_EQ(run.status, 0) << run.err;
  EXPECT_NE(run.out.find("lights     3"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("Lamp                         point at (-0.5, 1.5, 0.5), 0.07958 W/sr "
                         "(54.35 cd), power (1, 1, 1) W"),
            std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("Spot                         spot at (0.5, 2, -0.5), 0.1464 W/sr (100 "
                         "cd), cone 17.2..34.4 deg"),
            std::string::npos)
      << run.out;
}

// The panel's material with `doubleSided: true` emits from both faces: a light of twice one
// face's power, pi x 0.16 m^2 x 20 x 2 = 20.11 W, in the light list and in `lightbake info`.
// Before: 10.05 W, and doubleSided was not read.
TEST(BlenderStyleGltf, DoubleSidedEmissivePanelEmitsFromBothFaces) {
  const fs::path dir = test::fresh_dir("gltf_blender", "double_sided");
  test::write_blender_style_gltf(dir.string(), "one", {});
  test::write_blender_style_gltf(dir.string(), "two", {.double_sided_panel = true});
  const LoadResult one = load_scene((dir / "one.gltf").string());
  const LoadResult two = load_scene((dir / "two.gltf").string());
  const std::vector<AreaLight> one_light = collect_lights(one.scene);
  const std::vector<AreaLight> two_light = collect_lights(two.scene);
  ASSERT_EQ(one_light.size(), 1u);
  ASSERT_EQ(two_light.size(), 1u);
  EXPECT_FALSE(one_light[0].two_sided);
  EXPECT_TRUE(two_light[0].two_sided);
  const double face = std::numbers::pi * 0.16 * 20.0;
  EXPECT_NEAR(one_light[0].power.x, face, 1e-4 * face);
  EXPECT_NEAR(two_light[0].power.x, 2.0 * face, 1e-4 * face);
  EXPECT_EQ(two.warnings.size(), one.warnings.size());  // doubleSided is read, not warned about
  const test::CliRun run = test::run_lightbake("info two.gltf", dir.string());
  EXPECT_EQ(run.status, 0) << run.err;
  EXPECT_NE(run.out.find("area 0.16 m^2, both sides, power (20.11, 20.11, 20.11) W"),
            std::string::npos)
      << run.out;
}

// alphaMode MASK with an RGBA base colour texture whose alpha is a 0/1 checker: the loader
// keeps the alpha as a texture of its own and the cutoff, without a warning, and rays through
// the quad pass where alpha < 0.5 (half of them). Before: "MASK treated as OPAQUE", no ray
// passed.
TEST(BlenderStyleGltf, AlphaMaskCutsTheQuadWhereAlphaIsBelowTheCutoff) {
  const fs::path dir = test::fresh_dir("gltf_blender", "alpha_mask");
  const std::string path = test::write_textured_quad_gltf(
      dir.string(), "leaf", {{0, 1}, {1, 1}, {1, 0}, {0, 0}}, {}, "{}");
  std::vector<uint8_t> rgba;
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) rgba.insert(rgba.end(), {60, 160, 40, uint8_t((x + y) % 2 * 255)});
  write_png8((dir / "leaf.png").string(), 8, 8, 4, rgba);
  nlohmann::json document = nlohmann::json::parse(test::read_bytes(path));
  document["images"][0]["uri"] = "leaf.png";
  document["materials"][0]["alphaMode"] = "MASK";
  document["materials"][0]["alphaCutoff"] = 0.5;
  std::ofstream(path) << document.dump();

  const LoadResult result = load_scene(path);
  for (const std::string& warning : result.warnings)  // the only one: nothing emits light
    EXPECT_EQ(warning.find("alphaMode"), std::string::npos) << warning;
  const Material& leaf = result.scene.materials.at(0);
  ASSERT_TRUE(leaf.alpha_mask);
  EXPECT_EQ(leaf.alpha_cutoff, 0.5f);
  ASSERT_GE(leaf.alpha_texture, 0);
  const Texture& alpha = result.scene.textures.at(size_t(leaf.alpha_texture));
  EXPECT_EQ(alpha.channels, 1);
  EXPECT_EQ(alpha.texels.at(0), 0.0f);
  EXPECT_EQ(alpha.texels.at(1), 1.0f);

  const Accel accel(result.scene);
  constexpr int kSide = 64;
  int through = 0;
  for (int i = 0; i < kSide; ++i)
    for (int k = 0; k < kSide; ++k) {
      Ray ray;
      ray.origin = {(float(i) + 0.5f) / kSide, (float(k) + 0.5f) / kSide, 1.0f};
      ray.direction = {0, 0, -1};
      through += accel.occluded(ray) ? 0 : 1;
    }
  EXPECT_NEAR(double(through) / (kSide * kSide), 0.5, 0.01);
}

// What Blender 3.4's exporter writes for the corpus of tests/blender (make_scene.py): a
// Principled BSDF with Specular 0 becomes KHR_materials_specular with a black
// specularColorFactor (no specular layer: exactly lightbake's Lambert) plus KHR_materials_ior;
// a spot with blend 0 has innerConeAngle = outerConeAngle (outside the extension's rule, a
// hard-edged cone); every material is doubleSided. All of it loads without a warning of its
// own; a specular layer that is there (Specular 0.5) is still warned about, once.
TEST(BlenderStyleGltf, Blender34SpecularZeroBlendZeroAndDoubleSidedLoadWithoutWarnings) {
  const fs::path dir = test::fresh_dir("gltf_blender", "blender34");
  const std::string source = test::write_blender_style_gltf(dir.string(), "base", {});
  const size_t base_warnings = load_scene(source).warnings.size();
  std::ifstream in(source);
  nlohmann::json document = nlohmann::json::parse(in);
  in.close();
  for (auto& material : document["materials"]) {
    material["doubleSided"] = true;
    material["extensions"]["KHR_materials_specular"] = {{"specularColorFactor", {0, 0, 0}}};
    material["extensions"]["KHR_materials_ior"] = {{"ior", 1.45}};
  }
  auto& spot = document["extensions"]["KHR_lights_punctual"]["lights"][1]["spot"];
  spot["innerConeAngle"] = spot["outerConeAngle"];
  const std::string path = (dir / "blender34.gltf").string();
  std::ofstream(path) << document.dump();
  const LoadResult result = load_scene(path);
  EXPECT_EQ(result.warnings.size(), base_warnings) << all_warnings(result);
  EXPECT_TRUE(result.scene.materials.at(0).two_sided_reflection);  // the floor: diffuse
  EXPECT_TRUE(result.scene.materials.at(1).two_sided_emission);    // the panel
  ASSERT_EQ(result.scene.lights.size(), 2u);
  const Lamp& hard = result.scene.lights[1];
  EXPECT_EQ(hard.inner_cone, hard.outer_cone);
  EXPECT_EQ(spot_falloff(hard, std::cos(hard.outer_cone - 0.01f)), 1.0f);  // a hard edge
  EXPECT_EQ(spot_falloff(hard, std::cos(hard.outer_cone + 0.01f)), 0.0f);

  // Blender's default Specular 0.5: a specular layer lightbake does not render, warned once.
  for (auto& material : document["materials"])
    material["extensions"]["KHR_materials_specular"] = {
        {"specularColorFactor", {1.0, 1.0, 1.0}}};
  std::ofstream(path) << document.dump();
  const LoadResult specular = load_scene(path);
  EXPECT_EQ(specular.warnings.size(), base_warnings + 1) << all_warnings(specular);
  EXPECT_NE(all_warnings(specular).find(
                "at materials[0].extensions.KHR_materials_specular: unsupported material "
                "extension ignored"),
            std::string::npos)
      << all_warnings(specular);
}

}  // namespace
}  // namespace lb
