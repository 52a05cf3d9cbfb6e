// The native TOML loader on good input: shapes against their analytic areas and volumes,
// orientation, transforms, instancing, includes, power -> radiance, textures and the bundled
// scenes. Bad input lives in test_bad_input.cpp.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <glm/gtc/constants.hpp>
#include <map>

#include "bake/io/image_io.h"
#include "bake/io/scene_load.h"
#include "bake/io/shapes.h"
#include "bake/io/textures.h"
#include "bake/light_sources.h"
#include "bake/sky_light.h"
#include "test_helpers.h"

namespace lb {
namespace {

namespace fs = std::filesystem;
constexpr float kPi = glm::pi<float>();

// A fresh directory per test for the scene files it writes.
fs::path test_dir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const fs::path dir = fs::path(test::output_dir()) / "scene_toml" / info->name();
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string write_file(const fs::path& dir, const std::string& name, const std::string& text) {
  const fs::path path = dir / name;
  std::ofstream(path, std::ios::binary) << text;
  return path.string();
}

// Loads a scene from TOML text written to this test's directory.
LoadResult load_text(const std::string& toml, const std::string& name = "scene.toml") {
  const fs::path dir = test_dir();
  return load_scene(write_file(dir, name, toml));
}

const Material& material_named(const Scene& scene, const std::string& name) {
  for (const Material& material : scene.materials)
    if (material.name == name) return material;
  ADD_FAILURE() << "no material named " << name;
  return scene.materials.front();
}

const Mesh& mesh_named(const Scene& scene, const std::string& name) {
  for (const Mesh& mesh : scene.meshes)
    if (mesh.name == name) return mesh;
  ADD_FAILURE() << "no mesh named " << name;
  return scene.meshes.front();
}

// Volume enclosed by a closed mesh (divergence theorem); positive when fronts face out.
double signed_volume(const Mesh& mesh) {
  double volume = 0.0;
  for (uvec3 t : mesh.triangles)
    volume +=
        glm::dot(glm::dvec3(mesh.positions[t.x]),
                 glm::cross(glm::dvec3(mesh.positions[t.y]), glm::dvec3(mesh.positions[t.z]))) /
        6.0;
  return volume;
}

// Edges between welded positions and how many triangles use each: 2 everywhere = closed.
std::map<std::pair<uint32_t, uint32_t>, int> edge_uses(const Mesh& mesh) {
  std::map<std::tuple<float, float, float>, uint32_t> id;
  std::vector<uint32_t> welded;
  for (vec3 p : mesh.positions)
    welded.push_back(id.try_emplace({p.x, p.y, p.z}, id.size()).first->second);
  std::map<std::pair<uint32_t, uint32_t>, int> uses;
  for (uvec3 t : mesh.triangles)
    for (int k = 0; k < 3; ++k) {
      uint32_t a = welded[t[k]], b = welded[t[(k + 1) % 3]];
      ++uses[{std::min(a, b), std::max(a, b)}];
    }
  return uses;
}

void expect_closed(const Mesh& mesh) {
  for (const auto& [edge, count] : edge_uses(mesh))
    ASSERT_EQ(count, 2) << mesh.name << ": edge " << edge.first << "-" << edge.second;
}

// Every shading normal is unit and on the same side as its triangles' geometric normals.
void expect_consistent_normals(const Mesh& mesh) {
  ASSERT_EQ(mesh.normals.size(), mesh.positions.size());
  for (vec3 n : mesh.normals) ASSERT_NEAR(glm::length(n), 1.0f, 1e-5f);
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const vec3 g = triangle_normal(mesh, t);
    for (int k = 0; k < 3; ++k)
      ASSERT_GT(glm::dot(g, mesh.normals[mesh.triangles[t][k]]), 0.0f)
          << mesh.name << " triangle " << t;
  }
}

const char* kLight = R"(
[materials.lamp]
reflectance = 0
emission = 1
[[objects]]
name = "lamp"
shape = "quad"
size = 0.1
translate = [0, 10, 0]
normal = [0, -1, 0]
material = "lamp"
)";

// ---------------------------------------------------------------------------------------------

TEST(SceneToml, SphereAreaAndVolumeMatchAnalytic) {
  const LoadResult r = load_text(std::string(kLight) + R"(
[[objects]]
name = "ball"
shape = "sphere"
radius = 0.5
rings = 64
segments = 128
translate = [1, 2, 3]
)");
  EXPECT_TRUE(r.warnings.empty()) << r.warnings.front();
  const Mesh& ball = mesh_named(r.scene, "ball");
  // An inscribed polyhedron: area and volume fall short by O((pi/rings)^2), about 0.1% here.
  EXPECT_NEAR(mesh_area(ball), 4.0f * kPi * 0.25f, 0.002f * 4.0f * kPi * 0.25f);
  expect_closed(ball);
  expect_consistent_normals(ball);
  for (size_t v = 0; v < ball.positions.size(); ++v) {
    ASSERT_NEAR(glm::length(ball.positions[v] - vec3(1, 2, 3)), 0.5f, 1e-5f);
    ASSERT_GT(glm::dot(ball.normals[v], ball.positions[v] - vec3(1, 2, 3)), 0.0f);  // outward
  }
}

TEST(SceneToml, InwardBoxNormalsPointInside) {
  const LoadResult r = load_text(std::string(kLight) + R"(
[[objects]]
name = "room"
shape = "box"
min = [-2, 0, -1]
max = [2, 3, 1]
inward = true
)");
  const Mesh& room = mesh_named(r.scene, "room");
  EXPECT_FLOAT_EQ(mesh_area(room), 2.0f * (4 * 3 + 4 * 2 + 3 * 2));
  EXPECT_EQ(room.triangles.size(), 12u);
  expect_closed(room);
  expect_consistent_normals(room);
  const vec3 centre(0, 1.5f, 0);
  for (size_t t = 0; t < room.triangles.size(); ++t) {
    const vec3 on_face = room.positions[room.triangles[t].x];
    EXPECT_GT(glm::dot(triangle_normal(room, t), centre - on_face), 0.0f) << "triangle " << t;
  }
  EXPECT_LT(signed_volume(room), 0.0) << "an inward box encloses negative volume";
  EXPECT_NEAR(signed_volume(room), -24.0, 1e-4);
}

TEST(SceneToml, BoxFaceMaterialsSplitTheRoom) {
  const LoadResult r = load_text(std::string(kLight) + R"(
[materials]
white = { reflectance = 0.7 }
red = { reflectance = [0.7, 0.1, 0.1] }
[[objects]]
name = "room"
shape = "box"
size = 2
inward = true
material = "white"
face_materials = { left = "red", "+x" = "red" }
)");
  const Mesh& red = mesh_named(r.scene, "room[left,right]");
  const Mesh& white = mesh_named(r.scene, "room[floor,ceiling,back,front]");
  EXPECT_EQ(r.scene.materials[size_t(red.material)].name, "red");
  EXPECT_EQ(r.scene.materials[size_t(white.material)].name, "white");
  for (vec3 p : red.positions) EXPECT_FLOAT_EQ(std::abs(p.x), 1.0f);
  for (vec3 n : red.normals) EXPECT_FLOAT_EQ(std::abs(n.x), 1.0f);
  // Inward: the left wall (x = -1) faces +x.
  for (size_t v = 0; v < red.positions.size(); ++v)
    EXPECT_FLOAT_EQ(red.normals[v].x, -red.positions[v].x);
}

TEST(SceneToml, CylinderTorusAndRevolutionAreas) {
  const LoadResult r = load_text(std::string(kLight) + R"(
[[objects]]
name = "can"
shape = "cylinder"
radius = 0.5
height = 2
segments = 256
[[objects]]
name = "tube"
shape = "cylinder"
radius = 0.5
inner_radius = 0.4
height = 1
segments = 256
[[objects]]
name = "ring"
shape = "torus"
major_radius = 1
minor_radius = 0.25
rings = 128
segments = 256
[[objects]]
name = "wall"
shape = "revolution"
profile = [[0.5, 0], [0.5, 2]]
segments = 256
)");
  const float polygon = 256.0f / (2 * kPi) * std::sin(2 * kPi / 256.0f);  // inscribed 256-gon
  const Mesh& can = mesh_named(r.scene, "can");
  EXPECT_NEAR(mesh_area(can), polygon * 2 * kPi * 0.5f * 2 + 2 * polygon * kPi * 0.25f, 1e-3f);
  expect_closed(can);
  expect_consistent_normals(can);
  EXPECT_NEAR(signed_volume(can), polygon * kPi * 0.25 * 2, 1e-3);
  const Mesh& tube = mesh_named(r.scene, "tube");
  expect_closed(tube);
  expect_consistent_normals(tube);
  EXPECT_NEAR(signed_volume(tube), polygon * kPi * (0.25 - 0.16), 1e-3);
  const Mesh& ring = mesh_named(r.scene, "ring");
  EXPECT_NEAR(mesh_area(ring), 4 * kPi * kPi * 0.25f, 0.002f * 4 * kPi * kPi * 0.25f);
  expect_closed(ring);
  expect_consistent_normals(ring);
  EXPECT_NEAR(signed_volume(ring), 2 * kPi * kPi * 0.25 * 0.25, 0.002 * 2 * kPi * kPi * 0.0625);
  const Mesh& wall = mesh_named(r.scene, "wall");
  EXPECT_NEAR(mesh_area(wall), polygon * 2 * kPi * 0.5f * 2, 1e-3f);
  expect_consistent_normals(wall);
  for (size_t v = 0; v < wall.positions.size(); ++v)  // outer wall: normals point away from Y
    EXPECT_NEAR(glm::dot(wall.normals[v],
                         glm::normalize(vec3(wall.positions[v].x, 0, wall.positions[v].z))),
                1.0f, 1e-5f);
}

TEST(SceneToml, ThickRevolutionIsAClosedShell) {
  // A cup: flat bottom, straight wall; 2 cm walls make a closed solid with an inner cavity.
  const LoadResult r = load_text(std::string(kLight) + R"(
[[objects]]
name = "cup"
shape = "revolution"
profile = [[0, 0], [0.5, 0], [0.5, 1]]
thickness = 0.02
segments = 256
)");
  const Mesh& cup = mesh_named(r.scene, "cup");
  expect_closed(cup);
  expect_consistent_normals(cup);
  const double polygon = 256.0 / (2 * M_PI) * std::sin(2 * M_PI / 256.0);
  const double solid = polygon * M_PI * (0.25 * 1.0 - 0.48 * 0.48 * 0.98);
  EXPECT_NEAR(signed_volume(cup), solid, 1e-4);
  // The crease at the rim and the bottom edge is flat: some vertex normals point straight up.
  int up = 0;
  for (vec3 n : cup.normals) up += n.y > 0.9999f ? 1 : 0;
  EXPECT_GT(up, 0);
}

TEST(SceneToml, TransformsApplyScaleRotateTranslateInOrder) {
  const LoadResult r = load_text(std::string(kLight) + R"(
[[objects]]
name = "q"
shape = "quad"
size = [2, 1]
scale = 2
rotate = [90, 0, 0]           # +Y normal -> +Z
translate = [10, 0, 0]
[[objects]]
name = "axis"
shape = "quad"
size = 1
rotate = { axis = [0, 0, 1], angle = -90 }   # +Y normal -> +X
[[objects]]
name = "mirrored"
shape = "box"
size = 1
scale = [-1, 1, 1]
)");
  const Mesh& q = mesh_named(r.scene, "q");
  for (vec3 n : q.normals) {
    EXPECT_NEAR(n.x, 0.0f, 1e-6f);
    EXPECT_NEAR(n.y, 0.0f, 1e-6f);
    EXPECT_NEAR(n.z, 1.0f, 1e-6f);
  }
  EXPECT_NEAR(mesh_area(q), 2.0f * 1.0f * 4.0f, 1e-5f);
  const Bounds b = [&] {
    Bounds bounds;
    for (vec3 p : q.positions) bounds.extend(p);
    return bounds;
  }();
  // Scaled to 4 x 2, stood up in the XY plane, moved to x = 10.
  EXPECT_NEAR(b.min.x, 8.0f, 1e-5f);
  EXPECT_NEAR(b.max.x, 12.0f, 1e-5f);
  EXPECT_NEAR(b.min.y, -1.0f, 1e-5f);
  EXPECT_NEAR(b.max.y, 1.0f, 1e-5f);
  EXPECT_NEAR(b.max.z - b.min.z, 0.0f, 1e-5f);
  for (vec3 n : mesh_named(r.scene, "axis").normals) EXPECT_NEAR(n.x, 1.0f, 1e-6f);
  // A mirroring scale keeps fronts outside: winding is reversed along with the geometry.
  const Mesh& mirrored = mesh_named(r.scene, "mirrored");
  expect_consistent_normals(mirrored);
  EXPECT_NEAR(signed_volume(mirrored), 1.0, 1e-5);
}

TEST(SceneToml, InstancesPlaceEveryPartWithTheirTransforms) {
  const LoadResult r = load_text(std::string(kLight) + R"(
[materials]
wood = { reflectance = [0.5, 0.3, 0.2] }
metal = { type = "mirror" }

[[define.stool]]
name = "seat"
shape = "box"
min = [-0.2, 0.4, -0.2]
max = [0.2, 0.45, 0.2]
[[define.stool]]
name = "leg"
shape = "cylinder"
radius = 0.02
height = 0.4
translate = [0, 0.2, 0]
material = "metal"

[[define.pair]]
name = "a"
instance = "stool"
translate = [-1, 0, 0]
[[define.pair]]
name = "b"
instance = "stool"
translate = [1, 0, 0]

[[objects]]
name = "s1"
instance = "stool"
material = "wood"
translate = [5, 0, 0]
texel_size = 0.01
[[objects]]
name = "s2"
instance = "stool"
material = "wood"
rotate = [0, 90, 0]
[[objects]]
name = "twins"
instance = "pair"
material = "wood"
translate = [0, 0, 10]
)");
  ASSERT_EQ(r.scene.meshes.size(), 1u + 2u + 2u + 4u);  // lamp + s1 + s2 + twins (2 stools)
  const Mesh& seat = mesh_named(r.scene, "s1/seat");
  const Mesh& leg = mesh_named(r.scene, "s1/leg");
  EXPECT_EQ(r.scene.materials[size_t(seat.material)].name, "wood");  // inherited
  EXPECT_EQ(r.scene.materials[size_t(leg.material)].name, "metal");  // the part's own
  EXPECT_FLOAT_EQ(seat.bake.texel_size, 0.01f);
  for (vec3 p : seat.positions) EXPECT_NEAR(p.x, 5.0f, 0.2f + 1e-5f);
  for (vec3 p : leg.positions) {
    EXPECT_GE(p.y, -1e-6f);
    EXPECT_LE(p.y, 0.4f + 1e-6f);
  }
  const Mesh& nested = mesh_named(r.scene, "twins/b/seat");
  for (vec3 p : nested.positions) {
    EXPECT_NEAR(p.x, 1.0f, 0.2f + 1e-5f);
    EXPECT_NEAR(p.z, 10.0f, 0.2f + 1e-5f);
  }
  mesh_named(r.scene, "twins/a/leg");
  EXPECT_NEAR(mesh_area(mesh_named(r.scene, "s2/seat")), mesh_area(seat), 1e-6f);
}

TEST(SceneToml, PowerConvertsToRadianceByPiTimesArea) {
  const LoadResult r = load_text(R"(
[materials.panel]
reflectance = 0
power = [100, 50, 0]
[[objects]]
name = "big"
shape = "quad"
size = [0.5, 2]
material = "panel"
[[objects]]
name = "small"
shape = "quad"
size = [0.25, 0.5]
translate = [3, 0, 0]
material = "panel"
)");
  const Scene& scene = r.scene;
  const Material& big = scene.materials[size_t(mesh_named(scene, "big").material)];
  const Material& small = scene.materials[size_t(mesh_named(scene, "small").material)];
  EXPECT_FLOAT_EQ(big.emission.x, 100.0f / (kPi * 1.0f));
  EXPECT_FLOAT_EQ(big.emission.y, 50.0f / (kPi * 1.0f));
  EXPECT_EQ(big.emission.z, 0.0f);
  EXPECT_FLOAT_EQ(small.emission.x, 100.0f / (kPi * 0.125f));
  const auto lights = collect_lights(scene);
  ASSERT_EQ(lights.size(), 2u);
  for (const AreaLight& light : lights) {
    EXPECT_NEAR(light.power.x, 100.0f, 1e-3f);
    EXPECT_NEAR(light.power.y, 50.0f, 1e-3f);
  }
}

TEST(SceneToml, LightsChooseWhereTheirCausticRaysStart) {
  const LoadResult r = load_text(R"(
[materials.panel]
emission = 5
[[objects]]
name = "sharp"
shape = "quad"
material = "panel"
caustic_origins = "centre"
[[objects]]
name = "soft"
shape = "quad"
translate = [3, 0, 0]
material = "panel"
caustic_origins = "area"
[[objects]]
name = "plain"
shape = "quad"
translate = [6, 0, 0]
material = "panel"
)");
  EXPECT_EQ(mesh_named(r.scene, "sharp").bake.caustic_origins, CausticOrigins::centre);
  EXPECT_EQ(mesh_named(r.scene, "soft").bake.caustic_origins, CausticOrigins::over_light);
  EXPECT_EQ(mesh_named(r.scene, "plain").bake.caustic_origins, CausticOrigins::automatic);
  EXPECT_TRUE(r.warnings.empty());
}

TEST(SceneToml, ColourTexturesAreSrgbDecodedDataTexturesAreNot) {
  const fs::path dir = test_dir();
  fs::copy_file(test::source_dir() + "/tests/data/scene/srgb_levels.png", dir / "levels.png");
  const std::string path = write_file(dir, "scene.toml", std::string(kLight) + R"(
[materials.paint]
texture = "levels.png"
[materials.bumpy]
reflectance = 0.5
bump = { height = "levels.png", scale = 0.002 }
[[objects]]
shape = "quad"
material = "paint"
[[objects]]
shape = "quad"
material = "bumpy"
)");
  const LoadResult r = load_scene(path);
  ASSERT_EQ(r.scene.textures.size(), 2u);
  const Material& paint = material_named(r.scene, "paint");
  const Material& bumpy = material_named(r.scene, "bumpy");
  EXPECT_EQ(paint.reflectance, vec3(1.0f));  // a texture alone means white x texture
  const Texture& colour = r.scene.textures[size_t(paint.reflectance_texture)];
  const Texture& height = r.scene.textures[size_t(bumpy.bump_texture)];
  ASSERT_EQ(colour.width, 4);
  ASSERT_EQ(colour.channels, 3);
  EXPECT_TRUE(colour.srgb_decoded);
  EXPECT_FALSE(height.srgb_decoded);
  // Linear values of 8-bit sRGB codes 0, 128, 188, 64, 255 (IEC 61966-2-1).
  EXPECT_NEAR(colour.texels[0], 0.0f, 1e-6f);
  EXPECT_NEAR(colour.texels[3], 0.215861f, 1e-5f);
  EXPECT_NEAR(colour.texels[6], 0.502886f, 1e-5f);
  EXPECT_NEAR(colour.texels[7], 0.051269f, 1e-5f);
  EXPECT_NEAR(colour.texels[8], 1.0f, 1e-6f);
  EXPECT_NEAR(height.texels[3], 128.0f / 255.0f, 1e-6f);
  EXPECT_EQ(bumpy.bump, BumpKind::height);
  EXPECT_FLOAT_EQ(bumpy.bump_scale, 0.002f);
  // Bumped meshes get tangents orthogonal to their normals.
  for (const Mesh& mesh : r.scene.meshes) {
    if (r.scene.materials[size_t(mesh.material)].name != "bumpy") continue;
    ASSERT_EQ(mesh.tangents.size(), mesh.positions.size());
    for (size_t v = 0; v < mesh.tangents.size(); ++v) {
      EXPECT_NEAR(glm::length(vec3(mesh.tangents[v])), 1.0f, 1e-5f);
      EXPECT_NEAR(glm::dot(vec3(mesh.tangents[v]), mesh.normals[v]), 0.0f, 1e-5f);
      EXPECT_EQ(std::abs(mesh.tangents[v].w), 1.0f);
    }
  }
}

TEST(SceneToml, MeshFilesAreTriangulatedWithFlatNormalsAcrossCreases) {
  const fs::path dir = test_dir();
  write_file(dir, "cube.obj", R"(# unit cube, quads
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0 0 1
v 1 0 1
v 1 1 1
v 0 1 1
f 1 4 3 2
f 5 6 7 8
f 1 2 6 5
f 4 8 7 3
f 1 5 8 4
f 2 3 7 6
)");
  const std::string path = write_file(dir, "scene.toml", std::string(kLight) + R"(
[[objects]]
name = "cube"
mesh = "cube.obj"
scale = 2
translate = [0, 1, 0]
)");
  const LoadResult r = load_scene(path);
  EXPECT_TRUE(r.warnings.empty()) << r.warnings.front();
  const Mesh& cube = mesh_named(r.scene, "cube");
  EXPECT_EQ(cube.triangles.size(), 12u);
  EXPECT_EQ(cube.positions.size(), 24u);  // 90-degree creases split every corner three ways
  EXPECT_FLOAT_EQ(mesh_area(cube), 24.0f);
  EXPECT_NEAR(signed_volume(cube), 8.0, 1e-5);
  expect_consistent_normals(cube);
  for (size_t t = 0; t < cube.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(glm::dot(cube.normals[cube.triangles[t][k]], triangle_normal(cube, t)), 1.0f,
                  1e-6f);
}

TEST(SceneToml, UvsPutTheImageTopAtTheTopOfUprightFacesAndTileInMetres) {
  const fs::path dir = test_dir();
  // One triangle whose OBJ texture coordinates have v = 0 at the bottom (OpenGL convention).
  write_file(dir, "tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n");
  const LoadResult r = load_scene(write_file(dir, "scene.toml", std::string(kLight) + R"(
[[objects]]
name = "wall"
shape = "quad"
corner = [0, 0, 0]
edge_u = [2, 0, 0]
edge_v = [0, 1.5, 0]
uv_tile = 0.5
[[objects]]
name = "tri"
mesh = "tri.obj"
)"));
  const Mesh& wall = mesh_named(r.scene, "wall");
  for (size_t v = 0; v < wall.positions.size(); ++v) {
    // u = x / 0.5 m; v = (1.5 m - y) / 0.5 m: the image's top row is at the top of the wall.
    EXPECT_FLOAT_EQ(wall.uvs[v].x, wall.positions[v].x / 0.5f);
    EXPECT_FLOAT_EQ(wall.uvs[v].y, (1.5f - wall.positions[v].y) / 0.5f);
  }
  const Mesh& tri = mesh_named(r.scene, "tri");
  ASSERT_EQ(tri.uvs.size(), 3u);
  for (size_t v = 0; v < 3; ++v) EXPECT_FLOAT_EQ(tri.uvs[v].y, 1.0f - tri.positions[v].y);
}

TEST(SceneToml, IncludeOverridesAndRemovesByName) {
  const std::string scenes = test::source_dir() + "/scenes/";
  const LoadResult room = load_scene(scenes + "room.toml");
  const LoadResult no_ball = load_scene(scenes + "room_no_ball.toml");
  const LoadResult small = load_scene(scenes + "room_small_light.toml");
  const LoadResult two = load_scene(scenes + "room_two_blocks.toml");
  auto names = [](const Scene& s) {
    std::vector<std::string> n;
    for (const Mesh& m : s.meshes) n.push_back(m.name);
    return n;
  };
  auto has = [&](const Scene& s, const std::string& name) {
    const auto n = names(s);
    return std::find(n.begin(), n.end(), name) != n.end();
  };
  EXPECT_TRUE(has(room.scene, "ball"));
  EXPECT_FALSE(has(no_ball.scene, "ball"));
  EXPECT_EQ(no_ball.scene.meshes.size(), room.scene.meshes.size() - 1);
  EXPECT_FALSE(has(two.scene, "ball"));
  EXPECT_TRUE(has(two.scene, "block2"));
  // Same 150 W from a smaller light: radiance grows by the area ratio.
  const auto big_light = collect_lights(room.scene);
  const auto small_light = collect_lights(small.scene);
  ASSERT_EQ(big_light.size(), 1u);
  ASSERT_EQ(small_light.size(), 1u);
  EXPECT_NEAR(big_light[0].power.x, 150.0f, 1e-3f);
  EXPECT_NEAR(small_light[0].power.x, 150.0f, 1e-3f);
  EXPECT_NEAR(small_light[0].area, 0.0625f, 1e-6f);
  EXPECT_NEAR(small_light[0].radiance.x / big_light[0].radiance.x,
              big_light[0].area / small_light[0].area, 1e-4f);
}

// docs/gltf.md: a TOML file includes a .glb and adds what glTF cannot carry (a sky, lamps, bake
// settings); before, the binary .glb was parsed as TOML ("Encountered invalid utf-8 sequence").
TEST(SceneToml, IncludesAGlbAndAddsASkyLightsAndBakeSettings) {
  const fs::path dir = test_dir();
  const std::string glb = test::source_dir() + "/tests/data/gltf/room.glb";
  const LoadResult result = load_scene(write_file(dir, "room_sky.toml", R"(
include = ")" + glb + R"("
remove = ["ball"]
[sky]
radiance = 0.25
[bake]
quality = "draft"
[materials.block]
reflectance = 0.5
[[objects]]
name = "extra"
shape = "quad"
material = "walls"
translate = [2, 0.5, 2]
[[lights]]
type = "point"
position = [2, 2, 2]
intensity = 3
)"));
  const Scene& scene = result.scene;
  ASSERT_TRUE(scene.sky.has_value());
  EXPECT_EQ(scene.sky->radiance, vec3(0.25f));
  ASSERT_TRUE(scene.quality.has_value());
  EXPECT_EQ(*scene.quality, Quality::draft);
  // The glb's room, light and block (the ball removed by its node's name), then this file's quad.
  std::vector<std::string> names;
  for (const Mesh& mesh : scene.meshes) names.push_back(mesh.name);
  EXPECT_THAT(names, ::testing::ElementsAre("room", "light", "block", "extra"));
  EXPECT_EQ(scene.materials[size_t(mesh_named(scene, "extra").material)].name, "walls");
  // A TOML material replaces the glb's of the same name in place.
  EXPECT_EQ(scene.materials[size_t(mesh_named(scene, "block").material)].reflectance, vec3(0.5f));
  // The glb's 1 m^2 ceiling light of radiance 10: pi x 1 x 10 W; the camera comes along too.
  const std::vector<AreaLight> lights = collect_lights(scene);
  ASSERT_EQ(lights.size(), 1u);
  EXPECT_NEAR(lights[0].power.y, 10.0f * kPi, 1e-3f);
  ASSERT_EQ(scene.lights.size(), 1u);
  EXPECT_EQ(scene.lights[0].intensity, vec3(3.0f));
  EXPECT_EQ(scene.cameras.size(), 1u);
  const LightSources sources(scene);
  EXPECT_EQ(sources.size(), 3u);  // area light, lamp, sky
  for (const std::string& warning : result.warnings) ADD_FAILURE() << warning;
}

// A glb that emits nothing, lit by the TOML file that includes it (Blender's exporter writes no
// world: tests/blender's `world` scene): the glb alone is warned about, the whole scene is not.
TEST(SceneToml, AGlbLitByTheIncludingFilesSkyLoadsWithoutWarning) {
  const fs::path dir = test_dir();
  const std::string glb = test::source_dir() + "/tests/data/gltf/textured_quad.glb";
  const LoadResult alone = load_scene(glb);
  ASSERT_EQ(alone.warnings.size(), 1u);
  EXPECT_THAT(alone.warnings[0], ::testing::HasSubstr("nothing emits light"));
  const LoadResult lit = load_scene(
      write_file(dir, "quad_sky.toml", "include = \"" + glb + "\"\n[sky]\nradiance = 0.5\n"));
  ASSERT_TRUE(lit.scene.sky.has_value());
  for (const std::string& warning : lit.warnings) ADD_FAILURE() << warning;
  // Without the sky the whole scene is still dark, and said so once, naming the TOML file.
  const LoadResult dark =
      load_scene(write_file(dir, "quad_dark.toml", "include = \"" + glb + "\"\n"));
  ASSERT_EQ(dark.warnings.size(), 1u);
  EXPECT_THAT(dark.warnings[0], ::testing::HasSubstr("quad_dark.toml: nothing emits light"));
}

// [sky] rotation turns the image about +Y, right-handed: what it showed at direction d it shows
// at R(angle) d (here whole columns, so exactly); a sky lit in Blender reads right at -90
// (tests/blender's `hdr_world` checks that against Cycles).
TEST(SceneToml, SkyRotationTurnsTheImageAboutTheUpAxis) {
  const fs::path dir = test_dir();
  Image image(8, 4, 3);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 8; ++x) image.pixels[image.index(x, y)] = float(1 + x + 8 * y);
  write_image((dir / "columns.exr").string(), image);
  const auto sky_of = [&](const std::string& extra) {
    return load_scene(write_file(dir, "sky.toml", "[sky]\nimage = \"columns.exr\"\n" + extra));
  };
  const LoadResult plain = sky_of("");
  const Sky& plain_sky = *plain.scene.sky;
  const SkyLight original(plain_sky, &plain.scene.textures[size_t(plain_sky.texture)]);
  for (const double degrees : {90.0, -90.0, 45.0, 360.0}) {
    const LoadResult turned = sky_of("rotation = " + std::to_string(degrees) + "\n");
    const Sky& sky = *turned.scene.sky;
    const SkyLight rotated(sky, &turned.scene.textures[size_t(sky.texture)]);
    const double a = glm::radians(degrees);
    for (int row = 0; row < 4; ++row)
      for (int column = 0; column < 8; ++column) {  // every texel's centre
        const double phi = ((column + 0.5) / 8.0 - 0.5) * 2.0 * M_PI;
        const double theta = (row + 0.5) / 4.0 * M_PI;
        const glm::dvec3 d(std::sin(theta) * std::sin(phi), std::cos(theta),
                           -std::sin(theta) * std::cos(phi));
        const glm::dvec3 turned_d(d.x * std::cos(a) + d.z * std::sin(a), d.y,
                                  -d.x * std::sin(a) + d.z * std::cos(a));
        EXPECT_EQ(rotated.radiance(vec3(turned_d)), original.radiance(vec3(d)))
            << degrees << " degrees, column " << column << ", row " << row;
      }
  }
  EXPECT_THROW(load_scene(write_file(dir, "bad.toml", "[sky]\nradiance = 1\nrotation = 90\n")),
               SceneError);
}

// scenes/cornell_box.toml transcribes Mitsuba 3's cornell_box(): its light is a 0.46 x 0.38 m
// rectangle of radiance (18.387, 13.9873, 6.75357) W/(sr m^2), so power = pi L A; the box spans
// [-1, 1]^3 with the large block's base 1 cm below the floor.
TEST(SceneToml, CornellBoxMatchesMitsubasNumbers) {
  const LoadResult r = load_scene(test::source_dir() + "/scenes/cornell_box.toml");
  const auto lights = collect_lights(r.scene);
  ASSERT_EQ(lights.size(), 1u);
  const double area = 0.46 * 0.38;
  EXPECT_NEAR(lights[0].area, area, 1e-6);
  EXPECT_NEAR(lights[0].power.x, M_PI * 18.387 * area, 1e-4);  // 10.0972 W
  EXPECT_NEAR(lights[0].power.z, M_PI * 6.75357 * area, 1e-4);  // 3.7087 W
  const Bounds bounds = scene_bounds(r.scene);
  EXPECT_NEAR(bounds.min.y, -1.01f, 1e-5f);
  EXPECT_NEAR(bounds.max.x, 1.0f, 1e-6f);
  EXPECT_NEAR(bounds.min.z, -1.0f, 1e-6f);
  ASSERT_EQ(r.scene.cameras.size(), 1u);
  EXPECT_FLOAT_EQ(r.scene.cameras[0].vertical_fov_deg, 39.3077f);
}

TEST(SceneToml, CamerasCarryTheirExposureAndRejectAbsurdOnes) {
  const std::string camera = R"(
[[cameras]]
name = "dim"
position = [0, 1, 5]
target = [0, 1, 0]
fov = 40
exposure = -2.5
)";
  const LoadResult r = load_text(std::string(kLight) + camera);
  ASSERT_EQ(r.scene.cameras.size(), 1u);
  EXPECT_EQ(r.scene.cameras[0].exposure, -2.5f);
  EXPECT_EQ(r.scene.cameras[0].vertical_fov_deg, 40.0f);
  try {
    load_text(std::string(kLight) + "[[cameras]]\nposition = [0, 1, 5]\nexposure = 100\n");
    ADD_FAILURE() << "an exposure of 100 stops loaded";
  } catch (const SceneError& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("exposure must be in [-64, 64] stops"));
    EXPECT_THAT(e.what(), ::testing::HasSubstr("scene.toml:"));
  }
}

TEST(SceneToml, EveryBundledSceneLoadsCleanlyWithALight) {
  int count = 0;
  for (const auto& entry : fs::directory_iterator(test::source_dir() + "/scenes")) {
    if (entry.path().extension() != ".toml") continue;
    SCOPED_TRACE(entry.path().string());
    LoadResult r;
    ASSERT_NO_THROW(r = load_scene(entry.path().string()));
    for (const std::string& w : r.warnings) ADD_FAILURE() << "warning: " << w;
    EXPECT_FALSE(LightSources(r.scene).empty());
    EXPECT_FALSE(r.scene.cameras.empty());
    for (const Mesh& mesh : r.scene.meshes) expect_consistent_normals(mesh);
    ++count;
  }
  EXPECT_GE(count, 4);
}

// `double_sided = true`: the material emits from both faces; a power in watts is then the
// whole light's, half from each face (radiance = P / (2 pi A)).
TEST(SceneToml, DoubleSidedMaterialsEmitTheirPowerFromBothFaces) {
  const LoadResult result = load_text(R"(
[materials.panel]
power = 10
double_sided = true
[materials.glow]
emission = 2
double_sided = true
[[objects]]
shape = "quad"
size = 0.5
material = "panel"
[[objects]]
shape = "quad"
size = 1
material = "glow"
translate = [3, 0, 0]
)");
  EXPECT_TRUE(result.warnings.empty());
  const std::vector<AreaLight> lights = collect_lights(result.scene);
  ASSERT_EQ(lights.size(), 2u);
  EXPECT_TRUE(lights[0].two_sided);
  EXPECT_NEAR(lights[0].radiance.x, 10.0f / (2.0f * kPi * 0.25f), 1e-5f);
  EXPECT_NEAR(lights[0].power.x, 10.0f, 1e-4f);
  EXPECT_NEAR(lights[1].radiance.x, 2.0f, 0.0f);
  EXPECT_NEAR(lights[1].power.x, 2.0f * 2.0f * kPi, 1e-4f);
}

// `dynamic = true` marks a moving object, inherited through instances: load_scene moves its
// meshes out of the bake (Scene::dynamic_meshes, docs/light-probes.md); the rest stay.
TEST(SceneToml, DynamicObjectsLeaveTheBake) {
  const LoadResult r = load_text(std::string(kLight) + R"(
[[define.pair]]
name = "a"
shape = "sphere"
radius = 0.1
[[define.pair]]
name = "b"
shape = "quad"
[[objects]]
name = "ball"
shape = "sphere"
radius = 0.5
dynamic = true
[[objects]]
name = "cart"
instance = "pair"
dynamic = true
translate = [2, 0, 0]
[[objects]]
name = "floor"
shape = "quad"
)");
  std::vector<std::string> moving;
  for (const Mesh& mesh : r.scene.dynamic_meshes) moving.push_back(mesh.name);
  EXPECT_EQ(moving, (std::vector<std::string>{"ball", "cart/a", "cart/b"}));
  for (const Mesh& mesh : r.scene.meshes) {
    EXPECT_FALSE(mesh.dynamic) << mesh.name;
    EXPECT_EQ(mesh.name.find("cart"), std::string::npos);
  }
  EXPECT_NO_FATAL_FAILURE(mesh_named(r.scene, "floor"));
}

}  // namespace
}  // namespace lb
