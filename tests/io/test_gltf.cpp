// The glTF 2.0 loader on the fixtures written by scripts/make_gltf_fixtures.py: geometry and
// transforms, instancing, materials and their numbers, textures, cameras, and bad input.

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>

#include "bake/io/image_io.h"
#include "bake/io/scene_load.h"
#include "bake/lights.h"
#include "test_helpers.h"

namespace lb {
namespace {

std::string fixture(const std::string& name) {
  return test::source_dir() + "/tests/data/gltf/" + name;
}

const Mesh* find_mesh(const Scene& scene, const std::string& name) {
  for (const Mesh& mesh : scene.meshes)
    if (mesh.name == name) return &mesh;
  return nullptr;
}

const Material* find_material(const Scene& scene, const std::string& name) {
  for (const Material& material : scene.materials)
    if (material.name == name) return &material;
  return nullptr;
}

void expect_vec_near(vec3 actual, vec3 expected, float tolerance, const std::string& what) {
  EXPECT_NEAR(actual.x, expected.x, tolerance) << what;
  EXPECT_NEAR(actual.y, expected.y, tolerance) << what;
  EXPECT_NEAR(actual.z, expected.z, tolerance) << what;
}

// The one-line SceneError for `path`, checked to start with the path.
std::string error_for(const std::string& path, const SceneLoadOptions& options = {}) {
  try {
    load_scene(path, options);
  } catch (const SceneError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind(path + ": ", 0), 0u) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    return message;
  }
  ADD_FAILURE() << path << " loaded without an error";
  return "";
}

// The SceneError message for the fixture `file`.
std::string load_error(const std::string& file) {
  return error_for(fixture(file));
}

bool has_warning(const LoadResult& result, const std::string& part) {
  for (const std::string& warning : result.warnings)
    if (warning.find(part) != std::string::npos) return true;
  return false;
}

std::string all_warnings(const LoadResult& result) {
  std::string text;
  for (const std::string& warning : result.warnings) text += warning + "\n";
  return text;
}

// ---- Geometry, textures, lightmap UVs ---------------------------------------------------------

void expect_textured_quad(const LoadResult& result) {
  const Scene& scene = result.scene;
  ASSERT_EQ(scene.meshes.size(), 1u);
  const Mesh& mesh = scene.meshes[0];
  EXPECT_EQ(mesh.name, "floor");
  ASSERT_EQ(mesh.positions.size(), 4u);
  ASSERT_EQ(mesh.triangles.size(), 2u);
  EXPECT_EQ(mesh.triangles[0], uvec3(0, 1, 2));
  EXPECT_EQ(mesh.triangles[1], uvec3(0, 2, 3));
  expect_vec_near(mesh.positions[2], vec3(1, 1, 0), 0.0f, "corner");
  ASSERT_EQ(mesh.normals.size(), 4u);
  expect_vec_near(mesh.normals[3], vec3(0, 0, 1), 0.0f, "normal");
  // TEXCOORD_0 as written (v down the image, like Texture's top-row-first texels).
  ASSERT_EQ(mesh.uvs.size(), 4u);
  EXPECT_EQ(mesh.uvs[0], vec2(0, 1));
  EXPECT_EQ(mesh.uvs[2], vec2(1, 0));
  // TEXCOORD_1 kept as the lightmap UVs.
  ASSERT_EQ(mesh.lightmap_uvs.size(), 4u);
  EXPECT_EQ(mesh.lightmap_uvs[0], vec2(0.125f, 0.875f));
  EXPECT_EQ(mesh.lightmap_uvs[2], vec2(0.375f, 0.625f));

  ASSERT_EQ(scene.materials.size(), 1u);
  const Material& material = scene.materials[0];
  EXPECT_EQ(material.kind, MaterialKind::diffuse);
  EXPECT_EQ(material.reflectance, vec3(1.0f));  // white 1.0 must load as is
  ASSERT_EQ(material.reflectance_texture, 0);
  ASSERT_EQ(scene.textures.size(), 1u);
  const Texture& texture = scene.textures[0];
  EXPECT_EQ(texture.width, 2);
  EXPECT_EQ(texture.height, 2);
  ASSERT_EQ(texture.channels, 3);
  EXPECT_TRUE(texture.srgb_decoded);
  // Texels: top row white and sRGB 188 (linear 0.5029), bottom row black and red.
  const float grey = srgb_eotf(188.0f / 255.0f);
  EXPECT_NEAR(grey, 0.5029f, 1e-4f);
  const std::vector<float> expected = {1, 1, 1, grey, grey, grey, 0, 0, 0, 1, 0, 0};
  ASSERT_EQ(texture.texels.size(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i)
    EXPECT_NEAR(texture.texels[i], expected[i], 1e-6f) << i;
}

TEST(Gltf, TexturedQuadWithLightmapUvs) {
  const LoadResult result = load_scene(fixture("textured_quad.gltf"));
  expect_textured_quad(result);
  EXPECT_EQ(result.scene.source_path, fixture("textured_quad.gltf"));
}

TEST(Gltf, GlbMatchesGltf) {
  const LoadResult glb = load_scene(fixture("textured_quad.glb"));
  expect_textured_quad(glb);
  const LoadResult gltf = load_scene(fixture("textured_quad.gltf"));
  EXPECT_EQ(glb.scene.meshes[0].positions, gltf.scene.meshes[0].positions);
  EXPECT_EQ(glb.scene.textures[0].texels, gltf.scene.textures[0].texels);
}

TEST(Gltf, SparseStridedNormalisedStripAndFan) {
  const LoadResult result = load_scene(fixture("accessor_variants.gltf"));
  const Scene& scene = result.scene;
  ASSERT_EQ(scene.meshes.size(), 3u);
  // Sparse: vertex 2 replaced by (0, 2, 0); no NORMAL means no normals.
  const Mesh& sparse = scene.meshes[0];
  ASSERT_EQ(sparse.positions.size(), 3u);
  EXPECT_EQ(sparse.positions[1], vec3(1, 0, 0));
  EXPECT_EQ(sparse.positions[2], vec3(0, 2, 0));
  EXPECT_TRUE(sparse.normals.empty());
  // Interleaved 16-byte stride, UVs as normalised unsigned shorts, a strip of 4 -> 2 triangles,
  // both counter-clockwise seen from +z.
  const Mesh& strip = scene.meshes[1];
  ASSERT_EQ(strip.positions.size(), 4u);
  EXPECT_EQ(strip.positions[3], vec3(1, 1, 5));
  ASSERT_EQ(strip.uvs.size(), 4u);
  EXPECT_EQ(strip.uvs[1], vec2(1, 0));
  EXPECT_EQ(strip.uvs[3], vec2(1, 1));
  ASSERT_EQ(strip.triangles.size(), 2u);
  for (size_t t = 0; t < 2; ++t)
    expect_vec_near(triangle_normal(strip, t), vec3(0, 0, 1), 1e-6f, "strip");
  // A fan of 4 with unsigned int indices -> 2 triangles, counter-clockwise.
  const Mesh& fan = scene.meshes[2];
  ASSERT_EQ(fan.triangles.size(), 2u);
  for (size_t t = 0; t < 2; ++t)
    expect_vec_near(triangle_normal(fan, t), vec3(0, 0, 1), 1e-6f, "fan");
  EXPECT_NEAR(mesh_area(fan), 1.0f, 1e-6f);
  // No material: one shared plain diffuse default.
  ASSERT_EQ(scene.materials.size(), 1u);
  EXPECT_EQ(scene.materials[0].kind, MaterialKind::diffuse);
  EXPECT_EQ(scene.materials[0].reflectance, vec3(0.8f));
  for (const Mesh& mesh : scene.meshes) EXPECT_EQ(mesh.material, 0);
}

// ---- Transforms and instancing ----------------------------------------------------------------

TEST(Gltf, InstancedMeshTransformsPositionsAndNormals) {
  const LoadResult result = load_scene(fixture("instanced.gltf"));
  const Scene& scene = result.scene;
  ASSERT_EQ(scene.meshes.size(), 2u);

  // Node A: translation (1,2,3), 90 degrees about z, scale (2,1,1), applied as T R S to the
  // triangle (1,0,0), (0,1,0), (0,0,1) with normal (1,1,1)/sqrt(3).
  const Mesh* a = find_mesh(scene, "A");
  ASSERT_NE(a, nullptr);
  ASSERT_EQ(a->positions.size(), 3u);
  expect_vec_near(a->positions[0], vec3(1, 4, 3), 1e-6f, "A p0");
  expect_vec_near(a->positions[1], vec3(0, 2, 3), 1e-6f, "A p1");
  expect_vec_near(a->positions[2], vec3(1, 2, 4), 1e-6f, "A p2");
  // Inverse transpose: R S^-1 n = R (0.5, 1, 1) = (-1, 0.5, 1), normalised (-2, 1, 2)/3. A plain
  // R S n would give (-1, 2, 1)/sqrt(6) instead.
  for (vec3 n : a->normals) expect_vec_near(n, vec3(-2, 1, 2) / 3.0f, 1e-6f, "A normal");
  expect_vec_near(triangle_normal(*a, 0), vec3(-2, 1, 2) / 3.0f, 1e-6f, "A geometric normal");
  EXPECT_EQ(a->triangles[0], uvec3(0, 1, 2));
  EXPECT_FLOAT_EQ(a->bake.texel_size, 0.05f);  // from the node's extras
  EXPECT_EQ(a->bake.patch_size, 0.0f);
  EXPECT_EQ(a->bake.caustic_origins, CausticOrigins::over_light);

  // Node B: child of a matrix parent translating by (0,0,-5), scale (-1,1,1) mirrors, so the
  // winding flips to keep the geometric normal on the shading normal's side.
  const Mesh* b = find_mesh(scene, "B");
  ASSERT_NE(b, nullptr);
  expect_vec_near(b->positions[0], vec3(-1, 0, -5), 1e-6f, "B p0");
  expect_vec_near(b->positions[1], vec3(0, 1, -5), 1e-6f, "B p1");
  expect_vec_near(b->positions[2], vec3(0, 0, -4), 1e-6f, "B p2");
  const vec3 expected_b = vec3(-1, 1, 1) / std::sqrt(3.0f);
  for (vec3 n : b->normals) expect_vec_near(n, expected_b, 1e-6f, "B normal");
  EXPECT_EQ(b->triangles[0], uvec3(0, 2, 1));
  expect_vec_near(triangle_normal(*b, 0), expected_b, 1e-6f, "B geometric normal");
  EXPECT_EQ(a->material, b->material);
  EXPECT_EQ(scene.materials[size_t(a->material)].reflectance, vec3(0.5f));
}

TEST(Gltf, PerspectiveCameraFromNodeTransform) {
  const LoadResult result = load_scene(fixture("instanced.gltf"));
  ASSERT_EQ(result.scene.cameras.size(), 1u);
  const Camera& camera = result.scene.cameras[0];
  EXPECT_EQ(camera.name, "eye");
  expect_vec_near(camera.position, vec3(0, 1, 5), 1e-6f, "camera position");
  // Rotated 90 degrees about +y, the camera's -z looks along -x.
  expect_vec_near(glm::normalize(camera.target - camera.position), vec3(-1, 0, 0), 1e-6f,
                  "camera direction");
  expect_vec_near(camera.up, vec3(0, 1, 0), 1e-6f, "camera up");
  EXPECT_NEAR(camera.vertical_fov_deg, 0.7f * 180.0f / 3.14159265f, 1e-4f);
}

// ---- Materials --------------------------------------------------------------------------------

TEST(Gltf, MaterialKindsAndNumbers) {
  const LoadResult result = load_scene(fixture("materials.gltf"));
  const Scene& scene = result.scene;
  ASSERT_EQ(scene.materials.size(), 7u);
  ASSERT_EQ(scene.meshes.size(), 8u);  // one per primitive
  EXPECT_EQ(scene.meshes[0].name, "samples/samples.0");

  const Material* white = find_material(scene, "white");
  ASSERT_NE(white, nullptr);
  EXPECT_EQ(white->kind, MaterialKind::diffuse);
  EXPECT_EQ(white->reflectance, vec3(1.0f));
  EXPECT_FALSE(white->is_emitter());

  const Material* mirror = find_material(scene, "mirror");
  ASSERT_NE(mirror, nullptr);
  EXPECT_EQ(mirror->kind, MaterialKind::mirror);
  expect_vec_near(mirror->reflectance, vec3(0.9f), 1e-6f, "mirror reflectance");

  const Material* brushed = find_material(scene, "brushed");
  ASSERT_NE(brushed, nullptr);
  EXPECT_EQ(brushed->kind, MaterialKind::glossy);
  EXPECT_FLOAT_EQ(brushed->roughness, 0.4f);
  expect_vec_near(brushed->reflectance, vec3(0.8f, 0.6f, 0.4f), 1e-6f, "glossy reflectance");

  const Material* glass = find_material(scene, "glass");
  ASSERT_NE(glass, nullptr);
  EXPECT_EQ(glass->kind, MaterialKind::glass);
  EXPECT_FLOAT_EQ(glass->ior, 1.45f);
  EXPECT_EQ(glass->reflectance, vec3(1.0f));

  // radiance = emissiveFactor x emissiveStrength: (1, 0.5, 0.25) x 10.
  const Material* lamp = find_material(scene, "lamp");
  ASSERT_NE(lamp, nullptr);
  EXPECT_EQ(lamp->kind, MaterialKind::diffuse);
  expect_vec_near(lamp->emission, vec3(10.0f, 5.0f, 2.5f), 1e-6f, "lamp emission");
  EXPECT_EQ(lamp->reflectance, vec3(0.0f));
  // Without the strength extension the factor is the radiance.
  const Material* dim = find_material(scene, "dim_lamp");
  ASSERT_NE(dim, nullptr);
  expect_vec_near(dim->emission, vec3(0.5f, 0.0f, 0.0f), 1e-6f, "dim emission");

  const Material* bumpy = find_material(scene, "bumpy");
  ASSERT_NE(bumpy, nullptr);
  EXPECT_EQ(bumpy->kind, MaterialKind::diffuse);
  EXPECT_EQ(bumpy->bump, BumpKind::normal_map);
  EXPECT_FLOAT_EQ(bumpy->bump_scale, 0.5f);
  ASSERT_GE(bumpy->bump_texture, 0);
  const Texture& normal_map = scene.textures[size_t(bumpy->bump_texture)];
  EXPECT_FALSE(normal_map.srgb_decoded);  // data, stored as is: 128/255, 128/255, 1
  ASSERT_EQ(normal_map.texels.size(), 3u);
  EXPECT_NEAR(normal_map.texels[0], 128.0f / 255.0f, 1e-6f);
  EXPECT_NEAR(normal_map.texels[2], 1.0f, 1e-6f);
  EXPECT_FALSE(has_warning(result, "materials[")) << all_warnings(result);
}

TEST(Gltf, TangentsGeneratedForNormalMaps) {
  const LoadResult result = load_scene(fixture("materials.gltf"));
  const Scene& scene = result.scene;
  // Primitive 5: UVs aligned with x and (flipped) y: tangent +x, bitangent +y, w = +1.
  const Mesh& aligned = scene.meshes[5];
  ASSERT_EQ(aligned.tangents.size(), 3u);
  for (vec4 t : aligned.tangents) {
    expect_vec_near(vec3(t), vec3(1, 0, 0), 1e-6f, "aligned tangent");
    EXPECT_EQ(t.w, 1.0f);
  }
  // Primitive 7: u mirrored: tangent -x, and the bitangent still +y, so w = -1.
  const Mesh& mirrored = scene.meshes[7];
  ASSERT_EQ(mirrored.tangents.size(), 3u);
  for (vec4 t : mirrored.tangents) {
    expect_vec_near(vec3(t), vec3(-1, 0, 0), 1e-6f, "mirrored tangent");
    EXPECT_EQ(t.w, -1.0f);
  }
  // Meshes without a normal map get no tangents.
  EXPECT_TRUE(scene.meshes[0].tangents.empty());
}

// The Figure 8 room as a Blender-like .glb: what a bake needs is all there.
TEST(Gltf, RoomGlbLoadsForBaking) {
  const LoadResult result = load_scene(fixture("room.glb"));
  const Scene& scene = result.scene;
  ASSERT_EQ(scene.meshes.size(), 4u);
  // 6 + 1 + 6 quads, and a 16 x 32 UV sphere without degenerate pole triangles, as the file
  // holds them; load_scene then cuts the room's floor along the block (contact_conform.h).
  EXPECT_EQ(triangle_count(load_scene_gltf(fixture("room.glb")).scene),
            size_t(2 * 13 + 2 * 32 + 14 * 32 * 2));
  EXPECT_GT(triangle_count(scene), size_t(2 * 13 + 2 * 32 + 14 * 32 * 2));
  for (const Mesh& mesh : scene.meshes)
    EXPECT_EQ(mesh.lightmap_uvs.size(), mesh.positions.size()) << mesh.name;
  const Bounds bounds = scene_bounds(scene);
  expect_vec_near(bounds.min, vec3(0), 1e-6f, "room min");
  expect_vec_near(bounds.max, vec3(4, 3, 4), 1e-6f, "room max");

  // One 1 m^2 light of radiance 10 (1 x strength 10): pi x 1 x 10 W per channel, facing down.
  const std::vector<AreaLight> lights = collect_lights(scene);
  ASSERT_EQ(lights.size(), 1u);
  EXPECT_NEAR(lights[0].area, 1.0f, 1e-5f);
  expect_vec_near(lights[0].power, vec3(10.0f * 3.14159265f), 1e-3f, "light power");
  expect_vec_near(lights[0].normal, vec3(0, -1, 0), 1e-6f, "light normal");

  // The room is seen from inside, the block from outside: the floor faces up, the block's top
  // faces up too; the ball (radius 0.6 after scaling) is glass.
  const Mesh* ball = find_mesh(scene, "ball");
  ASSERT_NE(ball, nullptr);
  EXPECT_EQ(scene.materials[size_t(ball->material)].kind, MaterialKind::glass);
  EXPECT_FLOAT_EQ(scene.materials[size_t(ball->material)].ior, 1.5f);
  for (vec3 p : ball->positions) EXPECT_NEAR(glm::length(p - vec3(2.8f, 0.6f, 1.4f)), 0.6f, 1e-5f);
  EXPECT_NEAR(mesh_area(*ball), 4.0f * 3.14159265f * 0.36f, 0.05f);  // tessellated sphere
  const Mesh* room = find_mesh(scene, "room");
  ASSERT_NE(room, nullptr);
  EXPECT_NEAR(mesh_area(*room), 2 * 16 + 4 * 12, 1e-4f);
  for (size_t t = 0; t < room->triangles.size(); ++t) {
    const vec3 n = triangle_normal(*room, t);
    const vec3 centroid =
        (room->positions[room->triangles[t].x] + room->positions[room->triangles[t].y] +
         room->positions[room->triangles[t].z]) /
        3.0f;
    EXPECT_GT(glm::dot(n, vec3(2, 1.5f, 2) - centroid), 0.0f)
        << "room faces inward, triangle " << t;
  }
  ASSERT_EQ(scene.cameras.size(), 1u);
  EXPECT_NEAR(scene.cameras[0].vertical_fov_deg, glm::degrees(1.2f), 1e-4f);
}

// ---- Bad input --------------------------------------------------------------------------------

TEST(GltfBadInput, MissingFile) {
  const std::string message = load_error("bad/no_such_file.gltf");
  EXPECT_NE(message.find("no such file"), std::string::npos) << message;
}

TEST(GltfBadInput, JsonSyntaxError) {
  const std::string message = load_error("bad/syntax_error.gltf");
  // The JSON parser's position: line 3, where the stray comma is.
  EXPECT_NE(message.find("line 3"), std::string::npos) << message;
}

TEST(GltfBadInput, MissingBin) {
  const std::string message = load_error("bad/missing_bin.gltf");
  EXPECT_NE(message.find("does_not_exist.bin"), std::string::npos) << message;
}

TEST(GltfBadInput, TruncatedGlb) {
  std::string message = load_error("bad/truncated.glb");
  EXPECT_NE(message.find(": at byte 900: truncated .glb: the header declares 1800 bytes, the "
                         "file has 900"),
            std::string::npos)
      << message;
  message = load_error("bad/bad_chunk.glb");
  EXPECT_NE(message.find(": at byte 12 (chunk 0): chunk of 100000 bytes runs past the end"),
            std::string::npos)
      << message;
}

TEST(GltfBadInput, AccessorIndexOutOfRange) {
  const std::string message = load_error("bad/accessor_out_of_range.gltf");
  EXPECT_NE(
      message.find("at meshes[0].primitives[0].attributes.POSITION: accessor 42 out of range"),
      std::string::npos)
      << message;
}

TEST(GltfBadInput, VertexIndexOutOfRange) {
  const std::string message = load_error("bad/index_out_of_range.gltf");
  EXPECT_NE(message.find("at meshes[0].primitives[0].indices: index 7 at position 2 out of range "
                         "(3 vertices)"),
            std::string::npos)
      << message;
}

TEST(GltfBadInput, AccessorOverrunsBufferView) {
  std::string message = load_error("bad/bufferview_overrun.gltf");
  EXPECT_NE(message.find("meshes[0].primitives[0].attributes.POSITION"), std::string::npos)
      << message;
  EXPECT_NE(message.find("100 elements"), std::string::npos) << message;
  message = load_error("bad/accessor_offset_overrun.gltf");
  EXPECT_NE(message.find("at meshes[0].primitives[0].attributes.POSITION (accessors[0]): 3 "
                         "elements from byte 4 exceed bufferViews[0] of 36 bytes"),
            std::string::npos)
      << message;
}

TEST(GltfBadInput, UndecodableImageWarnsAndLoads) {
  const LoadResult result = load_scene(fixture("bad/bad_image.gltf"));
  EXPECT_TRUE(has_warning(result, fixture("bad/bad_image.gltf") + ": at images[0]: cannot decode"))
      << all_warnings(result);
  ASSERT_EQ(result.scene.materials.size(), 1u);
  EXPECT_EQ(result.scene.materials[0].reflectance_texture, -1);  // factor only
  EXPECT_TRUE(result.scene.textures.empty());
  EXPECT_EQ(result.scene.meshes.size(), 1u);
}

TEST(GltfBadInput, MissingImageWarnsAndLoads) {
  const std::string path = fixture("bad/missing_image.gltf");
  const LoadResult result = load_scene(path);
  EXPECT_TRUE(has_warning(result, path + ": at images[0]: image 'no_such_image.png' was not "
                                         "loaded; texture ignored"))
      << all_warnings(result);
  EXPECT_EQ(result.scene.materials[0].reflectance_texture, -1);
  EXPECT_EQ(result.scene.meshes.size(), 1u);
}

TEST(GltfBadInput, UnsupportedRequiredExtensionIsAnError) {
  const std::string message = load_error("bad/required_extension.gltf");
  EXPECT_NE(message.find("at extensionsRequired[0]: required extension KHR_draco_mesh_compression "
                         "is not supported"),
            std::string::npos)
      << message;
}

TEST(GltfBadInput, UnsupportedFeaturesWarnAndLoadWhatIsPossible) {
  const std::string path = fixture("bad/unsupported_features.gltf");
  const LoadResult result = load_scene(path);
  const std::string warnings = all_warnings(result);
  for (const char* expected : {
           ": at meshes[0].primitives[1].mode: mode 1",
           ": at materials[0].extensions.KHR_materials_clearcoat: unsupported",
           ": at cameras[0]: 'orthographic' camera not supported",
           ": at animations: 1 animation(s) ignored",
       }) {
    EXPECT_TRUE(has_warning(result, path + expected)) << expected << "\n" << warnings;
  }
  // What could be loaded was: the quad with its texture, no camera.
  ASSERT_EQ(result.scene.meshes.size(), 1u);
  EXPECT_EQ(result.scene.meshes[0].triangles.size(), 2u);
  EXPECT_EQ(result.scene.materials[0].reflectance_texture, 0);
  EXPECT_TRUE(result.scene.cameras.empty());
  // alphaMode BLEND is read (stochastic transparency by the texture's alpha), not warned of.
  EXPECT_FALSE(has_warning(result, "alphaMode")) << warnings;
  EXPECT_TRUE(result.scene.materials[0].alpha_blend);
  EXPECT_EQ(result.scene.materials[0].alpha_texture, 1);
  // KHR_texture_transform (required here) is honoured: scale 2 doubles the UVs, no warning.
  EXPECT_FALSE(has_warning(result, "KHR_texture_transform")) << warnings;
  float max_uv = 0.0f;
  for (vec2 uv : result.scene.meshes[0].uvs) max_uv = std::max({max_uv, uv.x, uv.y});
  EXPECT_EQ(max_uv, 2.0f);
  for (const std::string& warning : result.warnings)
    EXPECT_EQ(warning.find('\n'), std::string::npos) << warning;
}

// ---- Hostile input (issue 13): files generated here, each refused with its place ------------

namespace fs = std::filesystem;
using nlohmann::json;

fs::path hostile_dir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const fs::path dir = fs::path(test::output_dir()) / "gltf_hostile" / info->name();
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string base64(const std::string& bytes) {
  static const char* const kDigits =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < bytes.size(); i += 3) {
    uint32_t group = uint32_t(uint8_t(bytes[i])) << 16;
    if (i + 1 < bytes.size()) group |= uint32_t(uint8_t(bytes[i + 1])) << 8;
    if (i + 2 < bytes.size()) group |= uint32_t(uint8_t(bytes[i + 2]));
    out += kDigits[(group >> 18) & 63];
    out += kDigits[(group >> 12) & 63];
    out += i + 1 < bytes.size() ? kDigits[(group >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? kDigits[group & 63] : '=';
  }
  return out;
}

// One triangle in a data: URI buffer of 27 floats: positions (0..8), normals (9..17), uvs
// (18..23) and the indices 0, 1, 2 as floats (24..26, accessor 3, unused unless a test points
// primitives[0].indices at it).
struct Triangle {
  float values[27] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0,
                      1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 1, 2};
  std::string bytes() const {
    return std::string(reinterpret_cast<const char*>(values), sizeof values);
  }
  json document() const {
    auto accessor = [](int offset, int count, const char* type) {
      return json{{"bufferView", 0},
                  {"byteOffset", offset},
                  {"componentType", 5126},
                  {"count", count},
                  {"type", type}};
    };
    return json{{"asset", {{"version", "2.0"}}},
                {"scene", 0},
                {"scenes", {{{"nodes", {0}}}}},
                {"nodes", {{{"mesh", 0}}}},
                {"meshes",
                 {{{"primitives",
                    {{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}, {"TEXCOORD_0", 2}}}}}}}}},
                {"buffers",
                 {{{"byteLength", sizeof values},
                   {"uri", "data:application/octet-stream;base64," + base64(bytes())}}}},
                {"bufferViews", {{{"buffer", 0}, {"byteLength", sizeof values}}}},
                {"accessors",
                 {accessor(0, 3, "VEC3"), accessor(36, 3, "VEC3"), accessor(72, 3, "VEC2"),
                  accessor(96, 3, "SCALAR")}}};
  }
};

std::string write_gltf(const fs::path& dir, const std::string& text,
                       const std::string& name = "scene.gltf") {
  const fs::path path = dir / name;
  std::ofstream(path, std::ios::binary) << text;
  return path.string();
}

std::string hostile_error(const fs::path& dir, const json& document) {
  return error_for(write_gltf(dir, document.dump()));
}

TEST(GltfHostile, TwentyThousandDeepNodeChainLoadsWithoutRecursion) {
  // Before: SIGSEGV (stack overflow in the recursive node walk).
  json document = Triangle().document();
  constexpr int kDepth = 20000;
  json nodes = json::array();
  for (int i = 0; i < kDepth; ++i) {
    json node = {{"translation", {0.001, 0, 0}}};
    if (i + 1 < kDepth)
      node["children"] = {i + 1};
    else
      node["mesh"] = 0;
    nodes.push_back(node);
  }
  document["nodes"] = nodes;
  const LoadResult result = load_scene(write_gltf(hostile_dir(), document.dump()));
  ASSERT_EQ(result.scene.meshes.size(), 1u);
  // 20,000 translations of 1 mm, composed in double: the first vertex at x = 20 m.
  EXPECT_NEAR(result.scene.meshes[0].positions[0].x, 20.0f, 1e-4f);
}

TEST(GltfHostile, DeeplyNestedExtrasAreRefusedAtTheirByte) {
  // Before: SIGSEGV in tinygltf's recursive JSON conversion.
  const std::string head = R"({"asset": {"version": "2.0"}, "extras": )";
  const std::string text = head + std::string(200000, '[') + std::string(200000, ']') + "}";
  // The root object is level 1, so the 512th '[' opens level 513.
  const size_t offending = head.size() + 511;
  const fs::path dir = hostile_dir();
  std::string message = error_for(write_gltf(dir, text));
  EXPECT_NE(message.find(": at byte " + std::to_string(offending) +
                         ": JSON nested deeper than 512 levels"),
            std::string::npos)
      << message;
  // The same JSON as a .glb's JSON chunk (12-byte file header, 8-byte chunk header).
  std::string glb = "glTF";
  auto u32 = [&](uint32_t v) { glb.append(reinterpret_cast<const char*>(&v), 4); };
  u32(2);
  u32(uint32_t(20 + text.size()));
  u32(uint32_t(text.size()));
  glb += "JSON" + text;
  message = error_for(write_gltf(dir, glb, "scene.glb"));
  EXPECT_NE(message.find(": at byte " + std::to_string(20 + offending) +
                         ": JSON nested deeper than 512 levels"),
            std::string::npos)
      << message;
}

TEST(GltfHostile, NodeDagOfTwoToTheThirtyInstancesIsRefusedBeforeExpanding) {
  // Before: memory grew without end. 31 nodes, each placing the next twice.
  json document = Triangle().document();
  json nodes = json::array();
  for (int i = 0; i < 30; ++i) nodes.push_back({{"children", {i + 1, i + 1}}});
  nodes.push_back({{"mesh", 0}});
  document["nodes"] = nodes;
  const auto start = std::chrono::steady_clock::now();
  const std::string message = hostile_error(hostile_dir(), document);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_NE(message.find(": at scenes[0].nodes[0] (nodes[0]): the hierarchy expands to "
                         "1073741824 mesh instances (limit 200000"),
            std::string::npos)
      << message;
  EXPECT_LT(seconds, 1.0) << "counted, not expanded";
}

TEST(GltfHostile, NodeVisitsAndTrianglesAreCountedBeforeExpanding) {
  // 2^31 - 1 visits of empty nodes: no instance, still unbounded work.
  json document = Triangle().document();
  json nodes = json::array();
  for (int i = 0; i < 30; ++i) nodes.push_back({{"children", {i + 1, i + 1}}});
  nodes.push_back(json::object());
  document["nodes"] = nodes;
  std::string message = hostile_error(hostile_dir(), document);
  EXPECT_NE(message.find(": at scenes[0].nodes[0] (nodes[0]): the hierarchy expands to "
                         "2147483647 node visits (limit 1000000"),
            std::string::npos)
      << message;
  // One mesh whose accessor claims 150,000,003 vertices: 50,000,001 triangles, refused from the
  // count before the (much shorter) buffer is read.
  document = Triangle().document();
  document["accessors"][0]["count"] = 150000003;
  message = hostile_error(hostile_dir(), document);
  EXPECT_NE(message.find(": at scenes[0].nodes[0] (nodes[0]): the hierarchy expands to "
                         "50000001 triangles (limit 50000000"),
            std::string::npos)
      << message;
}

TEST(GltfHostile, CycleIsACycleAndNamesTheEdge) {
  json document = Triangle().document();
  document["nodes"] = {{{"children", {1}}}, {{"children", {0}}, {"mesh", 0}}};
  const std::string message = hostile_error(hostile_dir(), document);
  EXPECT_NE(message.find(": at nodes[1].children[0]: node hierarchy has a cycle through nodes[0]"),
            std::string::npos)
      << message;
}

TEST(GltfHostile, SilentlyAcceptedValuesAreRefusedWithTheirKeyPath) {
  const fs::path dir = hostile_dir();
  struct Case {
    std::function<void(json&)> edit;
    std::string expected;
  };
  auto camera = [](json perspective) {
    return json{{{"type", "perspective"}, {"perspective", perspective}}};
  };
  const std::vector<Case> cases = {
      {[](json& d) { d["asset"]["version"] = "1.0"; },
       ": at asset.version: glTF 1.0 is not supported (only glTF 2.0 is read)"},
      {[](json& d) { d["meshes"][0]["primitives"] = json::array(); },
       ": at meshes[0].primitives: empty; a mesh needs at least one primitive"},
      {[&](json& d) {
         d["cameras"] = camera({{"yfov", 1.0}, {"znear", 0.1}, {"aspectRatio", 0}});
       },
       ": at cameras[0].perspective.aspectRatio: must be positive, got 0"},
      {[&](json& d) {
         d["cameras"] = camera({{"yfov", 1.0}, {"znear", 0}, {"zfar", -1}});
       },
       ": at cameras[0].perspective.znear: must be positive, got 0"},
      {[&](json& d) {
         d["cameras"] = camera({{"yfov", 1.0}, {"znear", 0.1}, {"zfar", -1}});
       },
       ": at cameras[0].perspective.zfar: must exceed znear, got -1"},
      {[](json& d) { d["scene"] = -1; }, ": at scene: -1 is not a scene index"},
      {[](json& d) { d["meshes"][0]["primitives"][0]["indices"] = 3; },
       ": at meshes[0].primitives[0].indices: indices must be unsigned integers (componentType "
       "5126)"},
  };
  for (const Case& c : cases) {
    json document = Triangle().document();
    c.edit(document);
    const std::string message = hostile_error(dir, document);
    EXPECT_NE(message.find(c.expected), std::string::npos) << message;
  }
}

TEST(GltfHostile, HugeAndNonFiniteVertexDataIsRefusedNamingTheVertex) {
  const fs::path dir = hostile_dir();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  struct Case {
    int value;
    float number;
    std::string expected;
  };
  // Before, 3e38 loaded and printed an area of -nan.
  for (const Case& c : std::vector<Case>{
           {4, 3e38f,
            "mesh 'node0' (meshes[0]): vertex 1 coordinate (1, 3e+38, 0) is out of range"},
           {3, nan, "mesh 'node0' (meshes[0]): vertex 1 has a NaN or infinite coordinate"},
           {13, inf, "mesh 'node0' (meshes[0]): normals of vertex 1 is NaN or infinite"},
           {20, nan, "mesh 'node0' (meshes[0]): uvs of vertex 1 is NaN or infinite"}}) {
    Triangle triangle;
    triangle.values[c.value] = c.number;
    const std::string message = hostile_error(dir, triangle.document());
    EXPECT_NE(message.find(c.expected), std::string::npos) << message;
  }
}

TEST(GltfHostile, UrisStayInTheScenesFolderUnlessAllowed) {
  const fs::path dir = hostile_dir();
  const fs::path scene_dir = dir / "scene";
  fs::create_directories(scene_dir);
  const Triangle triangle;
  std::ofstream(dir / "outside.bin", std::ios::binary) << triangle.bytes();
  std::ofstream(scene_dir / "inside.bin", std::ios::binary) << triangle.bytes();
  fs::create_symlink("../outside.bin", scene_dir / "link.bin");
  auto with_uri = [&](const std::string& uri) {
    json document = triangle.document();
    document["buffers"][0]["uri"] = uri;
    return write_gltf(scene_dir, document.dump());
  };
  // Before, /etc/passwd was opened.
  std::string message = error_for(with_uri("/etc/passwd"));
  EXPECT_NE(message.find(": at buffers[0].uri: '/etc/passwd' is absolute; only files in the "
                         "scene's folder are read"),
            std::string::npos)
      << message;
  for (const std::string uri : {"../outside.bin", "sub/%2E%2E/%2e%2e/outside.bin", "link.bin"}) {
    message = error_for(with_uri(uri));
    EXPECT_NE(message.find(": at buffers[0].uri: '" + uri + "' points outside the scene's folder"),
              std::string::npos)
        << message;
  }
  EXPECT_EQ(load_scene(with_uri("inside.bin")).scene.meshes.size(), 1u);
  SceneLoadOptions allow;
  allow.allow_outside_uris = true;
  EXPECT_EQ(load_scene(with_uri("../outside.bin"), allow).scene.meshes.size(), 1u);
  EXPECT_EQ(load_scene(with_uri("link.bin"), allow).scene.meshes.size(), 1u);
}

TEST(GltfHostile, UnsupportedExtensionsWarnOncePerNameAndRequiredOnesAreRefused) {
  const fs::path dir = hostile_dir();
  json document = Triangle().document();
  document["extensionsUsed"] = {"EXT_made_up"};
  document["materials"] = {{{"extensions", {{"EXT_made_up", json::object()}}}},
                           {{"extensions", {{"EXT_made_up", json::object()}}}}};
  document["meshes"][0]["primitives"][0]["material"] = 1;
  const std::string path = write_gltf(dir, document.dump());
  const LoadResult result = load_scene(path);
  int mentions = 0;
  for (const std::string& warning : result.warnings)
    mentions += warning.find("EXT_made_up") != std::string::npos;
  EXPECT_EQ(mentions, 1) << all_warnings(result);
  EXPECT_TRUE(has_warning(result, path + ": at materials[0].extensions.EXT_made_up: unsupported "
                                         "material extension ignored"))
      << all_warnings(result);
  document["extensionsRequired"] = {"EXT_made_up"};
  const std::string message = hostile_error(dir, document);
  EXPECT_NE(message.find(": at extensionsRequired[0]: required extension EXT_made_up is not "
                         "supported"),
            std::string::npos)
      << message;
}

// A PNG signature and IHDR claiming width x height (CRC left zero: the size is checked first).
std::string png_header(uint32_t width, uint32_t height) {
  std::string png("\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR", 16);
  for (uint32_t v : {width, height})
    for (int shift = 24; shift >= 0; shift -= 8) png += char((v >> shift) & 0xff);
  png += std::string("\x08\x02\0\0\0\0\0\0\0", 9);
  return png;
}

TEST(GltfHostile, ImageClaimingTenGigapixelsIsNotDecoded) {
  // Before: std::bad_alloc. stb would allocate what the header claims.
  const fs::path dir = hostile_dir();
  std::ofstream(dir / "huge.png", std::ios::binary) << png_header(100000, 100000);
  json document = Triangle().document();
  document["images"] = {{{"uri", "huge.png"}}};
  document["textures"] = {{{"source", 0}}};
  document["materials"] = {
      {{"pbrMetallicRoughness", {{"metallicFactor", 0}, {"baseColorTexture", {{"index", 0}}}}}}};
  document["meshes"][0]["primitives"][0]["material"] = 0;
  const std::string path = write_gltf(dir, document.dump());
  const LoadResult result = load_scene(path);
  EXPECT_TRUE(
      has_warning(result, path + ": at images[0]: cannot decode image: the image claims 100000 "
                                 "x 100000 pixels, more than 1073741824 values"))
      << all_warnings(result);
  EXPECT_TRUE(result.scene.textures.empty());
}

// `extras.dynamic` on a node marks a moving object: load_scene moves it out of the bake
// (Scene::dynamic_meshes, docs/light-probes.md); Blender's 0/1 are read; anything else is an
// error naming the node.
// glTF's sampler (Blender's Image Texture interpolation and extension): the fixture's leaf
// texture is NEAREST, clamps u and mirrors v; its colour and its alpha (MASK) read the same.
TEST(Gltf, SamplersFilterAndWrapAsTheFileSays) {
  const LoadResult result = load_scene(fixture("alpha_leaf.glb"));
  EXPECT_TRUE(result.warnings.empty()) << result.warnings.front();
  const Material& leaf = result.scene.materials[size_t(result.scene.meshes[1].material)];
  for (const int t : {leaf.reflectance_texture, leaf.alpha_texture}) {
    ASSERT_GE(t, 0);
    const Texture& texture = result.scene.textures[size_t(t)];
    EXPECT_EQ(texture.filter, TextureFilter::nearest);
    EXPECT_EQ(texture.wrap_u, TextureWrap::clamp);
    EXPECT_EQ(texture.wrap_v, TextureWrap::mirror);
  }
  // Without a sampler: LINEAR and REPEAT.
  const LoadResult quad = load_scene(fixture("textured_quad.gltf"));
  const Texture& plain = quad.scene.textures.at(0);
  EXPECT_EQ(plain.filter, TextureFilter::linear);
  EXPECT_EQ(plain.wrap_u, TextureWrap::repeat);
  EXPECT_EQ(plain.wrap_v, TextureWrap::repeat);
}

TEST(GltfBadInput, UnknownWrapModeNamesTheSampler) {
  json document = Triangle().document();
  document["materials"] = {
      {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}, {"metallicFactor", 0}}}}};
  document["meshes"][0]["primitives"][0]["material"] = 0;
  document["textures"] = {{{"source", 0}, {"sampler", 0}}};
  document["samplers"] = {{{"wrapS", 12345}}};
  const fs::path dir = hostile_dir();
  fs::copy_file(fixture("checker.png"), dir / "checker.png");
  document["images"] = {{{"uri", "checker.png"}}};
  const std::string error = hostile_error(dir, document);
  EXPECT_NE(error.find("samplers[0].wrapS"), std::string::npos) << error;
  EXPECT_NE(error.find("12345"), std::string::npos) << error;
}

TEST(Gltf, ExtrasDynamicMovesTheNodeOutOfTheBake) {
  json document = Triangle().document();
  document["scenes"][0]["nodes"] = {0, 1, 2};
  document["nodes"] = {{{"mesh", 0}, {"name", "still"}},
                       {{"mesh", 0}, {"name", "moving"}, {"extras", {{"dynamic", true}}}},
                       {{"mesh", 0}, {"name", "blender"}, {"extras", {{"dynamic", 1}}}}};
  const LoadResult result = load_scene(write_gltf(hostile_dir(), document.dump()));
  ASSERT_EQ(result.scene.meshes.size(), 1u);
  EXPECT_EQ(result.scene.meshes[0].name, "still");
  ASSERT_EQ(result.scene.dynamic_meshes.size(), 2u);
  EXPECT_EQ(result.scene.dynamic_meshes[0].name, "moving");
  EXPECT_EQ(result.scene.dynamic_meshes[1].name, "blender");
  document["nodes"][1]["extras"]["dynamic"] = "yes";
  const std::string message = hostile_error(hostile_dir(), document);
  EXPECT_NE(message.find("nodes[1]"), std::string::npos) << message;
  EXPECT_NE(message.find("extras.dynamic must be true or false"), std::string::npos) << message;
}

}  // namespace
}  // namespace lb
