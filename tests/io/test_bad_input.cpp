// Bad input, one test per case of issue 2's list: every error is one line naming the file and
// the place (FILE:LINE:COL and the key path, or the mesh/material), warnings likewise, and
// nothing crashes. The last test runs `lightbake info` on a broken file.

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "bake/io/scene_load.h"
#include "test_helpers.h"

namespace lb {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;

fs::path test_dir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const fs::path dir = fs::path(test::output_dir()) / "bad_input" / info->name();
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string write_file(const fs::path& dir, const std::string& name, const std::string& bytes) {
  const fs::path path = dir / name;
  std::ofstream(path, std::ios::binary) << bytes;
  return path.string();
}

// A light, so only the case under test produces messages.
const std::string kLight = R"(
[materials.lamp]
emission = 1
[[objects]]
name = "lamp"
shape = "quad"
normal = [0, -1, 0]
translate = [0, 5, 0]
material = "lamp"
)";

// Loads and returns the SceneError's message; fails the test if nothing was thrown.
std::string load_error(const std::string& path) {
  try {
    load_scene(path);
  } catch (const SceneError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.find('\n'), std::string::npos) << "not one line: " << message;
    return message;
  }
  ADD_FAILURE() << "no SceneError for " << path;
  return "";
}

std::string load_error_text(const std::string& toml, const fs::path& dir) {
  return load_error(write_file(dir, "scene.toml", toml));
}

std::string join(const std::vector<std::string>& lines) {
  std::string all;
  for (const std::string& line : lines) all += line + "\n";
  return all;
}

// `scene.toml:LINE:` where the place must be.
std::string at_line(const fs::path& dir, int line) {
  return (dir / "scene.toml").string() + ":" + std::to_string(line) + ":";
}

std::string mesh_object(const std::string& file) {
  return kLight + "[[objects]]\nname = \"thing\"\nmesh = \"" + file + "\"\n";
}
// `mesh_object` puts the `mesh` key on this line of the scene file.
int mesh_key_line() {
  return int(std::count(kLight.begin(), kLight.end(), '\n')) + 3;
}

// ---------------------------------------------------------------------------------------------

TEST(BadInput, SyntaxErrorNamesFileLineAndColumn) {
  const fs::path dir = test_dir();
  const std::string message = load_error_text("[materials.wall]\nreflectance = [0.5, 0.5\n", dir);
  EXPECT_THAT(message, HasSubstr(at_line(dir, 2)));
  EXPECT_THAT(message, HasSubstr("TOML syntax error"));
}

TEST(BadInput, UnknownKeysWarnWithTheirPlace) {
  const fs::path dir = test_dir();
  const LoadResult r = load_scene(write_file(dir, "scene.toml", kLight + R"(
[materials.wall]
colour = [1, 0, 0]
[[objects]]
shape = "sphere"
radius = 1
material = "wall"
segmnts = 12
)"));
  const std::string warnings = join(r.warnings);
  EXPECT_THAT(warnings, HasSubstr(at_line(dir, 12) + "1: materials.wall.colour: unknown key"));
  EXPECT_THAT(warnings, HasSubstr(at_line(dir, 17) + "1: objects[1].segmnts: unknown key"));
  EXPECT_EQ(r.warnings.size(), 2u) << warnings;
  EXPECT_EQ(r.scene.meshes.size(), 2u);  // and the scene still loads
}

TEST(BadInput, MissingSceneFile) {
  const fs::path dir = test_dir();
  const std::string message = load_error((dir / "nowhere.toml").string());
  EXPECT_THAT(message, HasSubstr((dir / "nowhere.toml").string()));
  EXPECT_THAT(message, HasSubstr("does not exist"));
}

TEST(BadInput, MissingMeshFileNamesTheKeyAndTheFile) {
  const fs::path dir = test_dir();
  const std::string message = load_error_text(mesh_object("missing.obj"), dir);
  EXPECT_THAT(message, HasSubstr(at_line(dir, mesh_key_line()) + "8: objects[1].mesh"));
  EXPECT_THAT(message, HasSubstr((dir / "missing.obj").string()));
  EXPECT_THAT(message, HasSubstr("does not exist"));
}

TEST(BadInput, UnreadableFile) {
  const fs::path dir = test_dir();
  // A directory where a mesh should be: unreadable for everyone, root included.
  fs::create_directories(dir / "folder.obj");
  std::string message = load_error_text(mesh_object("folder.obj"), dir);
  EXPECT_THAT(message, HasSubstr(at_line(dir, mesh_key_line())));
  EXPECT_THAT(message, HasSubstr("folder.obj' is a directory"));
  if (geteuid() != 0) {  // permissions do not stop root
    const std::string locked = write_file(dir, "locked.toml", kLight);
    fs::permissions(locked, fs::perms::none);
    message = load_error(locked);
    EXPECT_THAT(message, HasSubstr("locked.toml"));
    EXPECT_THAT(message, HasSubstr("cannot read"));
  }
}

// 84-byte header claiming 2 triangles, then only one 50-byte record.
TEST(BadInput, TruncatedBinaryStl) {
  const fs::path dir = test_dir();
  std::string stl(80, ' ');
  const uint32_t count = 2;
  stl.append(reinterpret_cast<const char*>(&count), 4);
  stl.append(50, '\0');
  write_file(dir, "part.stl", stl);
  const std::string message = load_error_text(mesh_object("part.stl"), dir);
  EXPECT_THAT(message, HasSubstr(at_line(dir, mesh_key_line())));
  EXPECT_THAT(message, HasSubstr("truncated binary STL"));
  EXPECT_THAT(message, HasSubstr("part.stl"));
}

TEST(BadInput, TruncatedBinaryPly) {
  const fs::path dir = test_dir();
  std::string ply =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
      "property float y\nproperty float z\nelement face 1\n"
      "property list uchar int vertex_indices\nend_header\n";
  const float xyz[6] = {0, 0, 0, 1, 0, 0};  // two of the three vertices, and no face
  ply.append(reinterpret_cast<const char*>(xyz), sizeof xyz);
  write_file(dir, "part.ply", ply);
  const std::string message = load_error_text(mesh_object("part.ply"), dir);
  EXPECT_THAT(message, HasSubstr(at_line(dir, mesh_key_line())));
  EXPECT_THAT(message, HasSubstr("truncated binary PLY"));
  EXPECT_THAT(message, HasSubstr("part.ply"));
}

TEST(BadInput, TruncatedOpenMeshFile) {
  const fs::path dir = test_dir();
  OpenMesh::TriMesh_ArrayKernelT<> cube;
  std::vector<OpenMesh::VertexHandle> v;
  for (int i = 0; i < 8; ++i)
    v.push_back(cube.add_vertex({float(i & 1), float((i >> 1) & 1), float((i >> 2) & 1)}));
  const int faces[12][3] = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                            {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  for (const auto& f : faces) cube.add_face(v[size_t(f[0])], v[size_t(f[1])], v[size_t(f[2])]);
  const std::string full = (dir / "full.om").string();
  ASSERT_TRUE(OpenMesh::IO::write_mesh(cube, full));
  std::ifstream in(full, std::ios::binary);
  std::stringstream bytes;
  bytes << in.rdbuf();
  write_file(dir, "cube.om", bytes.str().substr(0, bytes.str().size() / 2));
  const std::string message = load_error_text(mesh_object("cube.om"), dir);
  EXPECT_THAT(message, HasSubstr(at_line(dir, mesh_key_line())));
  EXPECT_THAT(message, HasSubstr("truncated OM file '"));
  EXPECT_THAT(message, HasSubstr("cube.om': header promises 8 vertices and 12 faces"));
}

TEST(BadInput, ObjFaceIndexOutOfRangeNamesTheObjLine) {
  const fs::path dir = test_dir();
  write_file(dir, "tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 9\n");
  const std::string message = load_error_text(mesh_object("tri.obj"), dir);
  EXPECT_THAT(message, HasSubstr(at_line(dir, mesh_key_line())));
  EXPECT_THAT(message, HasSubstr("tri.obj:5: face index 9 out of range (3 vertices"));
}

TEST(BadInput, TriangleIndexOutOfRangeInCodeBuiltScene) {
  // The glTF loader relies on validate_scene for this; it must name the mesh and triangle.
  Scene scene;
  scene.source_path = "built.gltf";
  scene.materials.push_back(Material{});
  Mesh mesh;
  mesh.name = "broken";
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  scene.meshes.push_back(mesh);
  std::vector<std::string> warnings;
  try {
    validate_scene(scene, warnings);
    FAIL() << "no SceneError";
  } catch (const SceneError& e) {
    EXPECT_THAT(std::string(e.what()),
                HasSubstr("built.gltf: mesh 'broken' (meshes[0]): triangle 1 has a vertex index "
                          "out of range"));
  }
}

TEST(BadInput, WrongTypeNamesKeyPathAndTypes) {
  const fs::path dir = test_dir();
  const std::string message =
      load_error_text(kLight + "[materials.wall]\nreflectance = \"red\"\n", dir);
  EXPECT_THAT(message, HasSubstr(at_line(dir, 11) + "15: materials.wall.reflectance"));
  EXPECT_THAT(message, HasSubstr("expected a number or an array of 3 numbers, got string"));
}

TEST(BadInput, WrongArrayLengthNamesTheKey) {
  const fs::path dir = test_dir();
  const std::string message =
      load_error_text(kLight + "[[objects]]\nshape = \"sphere\"\ntranslate = [1, 2]\n", dir);
  EXPECT_THAT(message, HasSubstr(at_line(dir, 12) + "13: objects[1].translate"));
  EXPECT_THAT(message, HasSubstr("expected an array of 3 numbers, got an array of 2"));
}

TEST(BadInput, ReflectanceAboveOne) {
  const fs::path dir = test_dir();
  const std::string message =
      load_error_text(kLight + "[materials.wall]\nreflectance = [0.5, 1.2, 0.5]\n", dir);
  EXPECT_THAT(message, HasSubstr(at_line(dir, 11) + "15: materials.wall.reflectance"));
  EXPECT_THAT(message, HasSubstr("(0.5, 1.2, 0.5) is outside [0, 1]"));
}

TEST(BadInput, ReflectanceAboveOneInCodeBuiltScene) {
  Scene scene;
  scene.source_path = "built.gltf";
  Material m;
  m.name = "hot";
  m.reflectance = vec3(1.5f, 0.5f, 0.5f);
  scene.materials.push_back(m);
  std::vector<std::string> warnings;
  try {
    validate_scene(scene, warnings);
    FAIL() << "no SceneError";
  } catch (const SceneError& e) {
    EXPECT_THAT(std::string(e.what()),
                HasSubstr("built.gltf: material 'hot' (materials[0]): reflectance"));
  }
}

TEST(BadInput, NegativeRadiance) {
  const fs::path dir = test_dir();
  const std::string message =
      load_error_text(kLight + "[materials.glow]\nemission = [1, -2, 1]\n", dir);
  EXPECT_THAT(message, HasSubstr(at_line(dir, 11) + "12: materials.glow.emission"));
  EXPECT_THAT(message, HasSubstr("negative radiance"));
}

TEST(BadInput, NegativePower) {
  const fs::path dir = test_dir();
  const std::string message = load_error_text(kLight + "[materials.glow]\npower = -100\n", dir);
  EXPECT_THAT(message, HasSubstr(at_line(dir, 11) + "9: materials.glow.power"));
  EXPECT_THAT(message, HasSubstr("negative power"));
}

TEST(BadInput, IorBelowOne) {
  const fs::path dir = test_dir();
  const std::string message =
      load_error_text(kLight + "[materials.glass]\ntype = \"glass\"\nior = 0.8\n", dir);
  EXPECT_THAT(message, HasSubstr(at_line(dir, 12) + "7: materials.glass.ior"));
  EXPECT_THAT(message, HasSubstr("index of refraction 0.8 is below 1"));
}

TEST(BadInput, GlossyRoughnessOutOfRange) {
  const fs::path dir = test_dir();
  const std::string message =
      load_error_text(kLight + "[materials.plate]\ntype = \"glossy\"\nroughness = 0\n", dir);
  EXPECT_THAT(message, HasSubstr(at_line(dir, 12) + "13: materials.plate.roughness"));
  EXPECT_THAT(message, HasSubstr("outside (0, 1]"));
}

TEST(BadInput, NanCoordinateInSceneFile) {
  const fs::path dir = test_dir();
  const std::string message =
      load_error_text(kLight + "[[objects]]\nshape = \"sphere\"\ntranslate = [0, nan, 0]\n", dir);
  EXPECT_THAT(message, HasSubstr(at_line(dir, 12) + "17: objects[1].translate[1]"));
  EXPECT_THAT(message, HasSubstr("is not finite"));
}

TEST(BadInput, InfiniteCoordinateInMeshFile) {
  const fs::path dir = test_dir();
  write_file(dir, "tri.obj", "v 0 0 0\nv 1 inf 0\nv 0 1 0\nf 1 2 3\n");
  const std::string message = load_error_text(mesh_object("tri.obj"), dir);
  EXPECT_THAT(message, HasSubstr(at_line(dir, mesh_key_line())));
  EXPECT_THAT(message, HasSubstr("tri.obj:2: vertex coordinate 'inf' is not finite"));
}

TEST(BadInput, NanPositionInCodeBuiltScene) {
  Scene scene;
  scene.source_path = "built.gltf";
  scene.materials.push_back(Material{});
  Mesh mesh;
  mesh.name = "tri";
  mesh.positions = {{0, 0, 0}, {1, std::nanf(""), 0}, {0, 1, 0}};
  mesh.triangles = {{0, 1, 2}};
  scene.meshes.push_back(mesh);
  std::vector<std::string> warnings;
  try {
    validate_scene(scene, warnings);
    FAIL() << "no SceneError";
  } catch (const SceneError& e) {
    EXPECT_THAT(std::string(e.what()),
                HasSubstr("built.gltf: mesh 'tri' (meshes[0]): vertex 1 has a NaN"));
  }
}

TEST(BadInput, NonUnitNormalsAreNormalisedAndZeroOnesReplaced) {
  Scene scene;
  scene.source_path = "built.gltf";
  Material lamp;
  lamp.emission = vec3(1.0f);
  scene.materials.push_back(lamp);
  Mesh mesh;
  mesh.name = "tri";
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.normals = {{0, 0, 2}, {0, 0, 0.5f}, {0, 0, 0}};
  mesh.triangles = {{0, 1, 2}};
  scene.meshes.push_back(mesh);
  std::vector<std::string> warnings;
  validate_scene(scene, warnings);
  for (vec3 n : scene.meshes[0].normals) EXPECT_EQ(n, vec3(0, 0, 1));
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_THAT(warnings[0], HasSubstr("built.gltf: mesh 'tri' (meshes[0]): 1 zero-length normals "
                                     "replaced"));
}

TEST(BadInput, EmptyMesh) {
  const fs::path dir = test_dir();
  write_file(dir, "empty.obj", "# vertices but no faces\nv 0 0 0\nv 1 0 0\nv 0 1 0\n");
  const std::string message = load_error_text(mesh_object("empty.obj"), dir);
  EXPECT_THAT(message, HasSubstr(at_line(dir, mesh_key_line())));
  EXPECT_THAT(message, HasSubstr("empty.obj' holds no triangles"));
}

TEST(BadInput, DegenerateAndZeroAreaTrianglesAreDroppedAndCounted) {
  const fs::path dir = test_dir();
  // Two good triangles, one with a repeated vertex, two with collinear vertices.
  write_file(dir, "quad.obj",
             "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\n"
             "f 1 2 3\nf 1 3 4\nf 1 1 2\nf 1 2 5\nf 2 5 1\n");
  const LoadResult r = load_scene(write_file(dir, "scene.toml", mesh_object("quad.obj")));
  const std::string warnings = join(r.warnings);
  EXPECT_THAT(warnings, HasSubstr("quad.obj': dropped 1 face(s) that repeat a vertex"));
  EXPECT_THAT(warnings, HasSubstr(at_line(dir, 10) + "1: objects[1]: mesh 'thing': dropped 2 of 4 "
                                                     "triangles (0 degenerate, 2 zero-area)"));
  ASSERT_EQ(r.scene.meshes.size(), 2u);
  EXPECT_EQ(r.scene.meshes[1].triangles.size(), 2u);
  EXPECT_FLOAT_EQ(mesh_area(r.scene.meshes[1]), 1.0f);
}

TEST(BadInput, NonManifoldMeshIsWarnedAndKept) {
  const fs::path dir = test_dir();
  // Three triangles sharing the edge 1-2: a "book" with three pages.
  write_file(dir, "book.obj",
             "v 0 0 0\nv 0 1 0\nv 1 0 0\nv -1 0 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n");
  const LoadResult r = load_scene(write_file(dir, "scene.toml", mesh_object("book.obj")));
  const std::string warnings = join(r.warnings);
  EXPECT_THAT(warnings,
              HasSubstr(at_line(dir, 10) + "1: objects[1]: mesh 'thing': non-manifold: "
                                           "1 edge(s) shared by more than two triangles"));
  EXPECT_EQ(r.scene.meshes[1].triangles.size(), 3u);
}

TEST(BadInput, TextureThatFailsToDecode) {
  const fs::path dir = test_dir();
  write_file(dir, "broken.png", "\x89PNG\r\n\x1a\n this is not really a PNG");
  const std::string message =
      load_error_text(kLight + "[materials.wall]\ntexture = \"broken.png\"\n", dir);
  EXPECT_THAT(message, HasSubstr(at_line(dir, 11) + "11: materials.wall.texture"));
  EXPECT_THAT(message, HasSubstr("cannot decode texture"));
  EXPECT_THAT(message, HasSubstr("broken.png"));
}

TEST(BadInput, MissingTexture) {
  const fs::path dir = test_dir();
  const std::string message =
      load_error_text(kLight + "[materials.wall]\nbump = { height = \"nowhere.png\" }\n", dir);
  EXPECT_THAT(message, HasSubstr(at_line(dir, 11) + "19: materials.wall.bump.height"));
  EXPECT_THAT(message, HasSubstr("nowhere.png' does not exist"));
}

TEST(BadInput, NoLightIsAWarningNotAnError) {
  const fs::path dir = test_dir();
  const LoadResult r =
      load_scene(write_file(dir, "scene.toml", "[[objects]]\nshape = \"box\"\ninward = true\n"));
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_THAT(r.warnings[0], HasSubstr((dir / "scene.toml").string() + ": nothing emits light"));
  EXPECT_EQ(r.scene.meshes.size(), 1u);
}

TEST(BadInput, UnknownNamesAndCycles) {
  const fs::path dir = test_dir();
  EXPECT_THAT(load_error_text(kLight + "[[objects]]\nshape = \"cone\"\n", dir),
              HasSubstr(at_line(dir, 11) + "9: objects[1].shape: unknown shape 'cone'"));
  EXPECT_THAT(load_error_text(kLight + "[[objects]]\nshape = \"box\"\nmaterial = \"gold\"\n", dir),
              HasSubstr("objects[1].material: no material named 'gold' (defined: lamp)"));
  EXPECT_THAT(load_error_text(
                  kLight + "[[define.a]]\ninstance = \"a\"\n[[objects]]\ninstance = \"a\"\n", dir),
              HasSubstr("define.a[0].instance: definition 'a' places itself"));
  write_file(dir, "loop.toml", "include = \"loop.toml\"\n");
  EXPECT_THAT(load_error((dir / "loop.toml").string()), HasSubstr("include cycle"));
}

TEST(BadInput, UnknownCausticOriginsNamesTheValues) {
  const fs::path dir = test_dir();
  const std::string message = load_error_text(kLight + "caustic_origins = \"everywhere\"\n", dir);
  EXPECT_THAT(message, HasSubstr(":10:19: "));
  EXPECT_THAT(message, HasSubstr("caustic_origins is 'centre' or 'area', not 'everywhere'"));
}

// Runs `lightbake ARGS` with stdout to DIR/out.txt and stderr to DIR/err.txt, expects a
// non-zero exit, and returns what it wrote to stderr.
// `prefix`: a command to run lightbake under (e.g. "timeout 20 "); lightbake runs in `dir`.
std::string run_failing_cli(const std::string& args, const fs::path& dir,
                            const std::string& prefix = "") {
  const std::string binary = std::string(LIGHTBAKE_BINARY_DIR) + "/app/lightbake";
  EXPECT_TRUE(fs::exists(binary)) << binary << " (test_bad_input depends on the lightbake target)";
  const std::string command = "cd '" + dir.string() + "' && " + prefix + "'" + binary + "' " +
                              args + " > '" + (dir / "out.txt").string() + "' 2> '" +
                              (dir / "err.txt").string() + "'";
  const int status = std::system(command.c_str());
  EXPECT_TRUE(WIFEXITED(status));
  EXPECT_NE(WEXITSTATUS(status), 0) << command;
  std::ifstream err(dir / "err.txt");
  std::stringstream buffer;
  buffer << err.rdbuf();
  return buffer.str();
}

// A FIFO opened for reading blocks until a writer comes: as a texture, a sky image, a glTF
// image or a compared image it is refused at once, naming the file (issue 42). `timeout`
// turns a hang into a failure instead of a stuck test.
TEST(BadInput, FifoTextureSkyAndImageInputsAreRefusedAtOnce) {
  const fs::path dir = test_dir();
  const std::string fifo = (dir / "pipe.png").string();
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0) << std::strerror(errno);
  write_file(dir, "texture.toml", kLight + "[materials.wall]\ntexture = 'pipe.png'\n" +
                                      "[[objects]]\nname = 'floor'\nshape = 'quad'\n" +
                                      "material = 'wall'\n");
  write_file(dir, "sky.toml", kLight + "[sky]\nimage = 'pipe.png'\n");
  write_file(dir, "image.gltf",
             R"({"asset": {"version": "2.0"}, "images": [{"uri": "pipe.png"}]})");
  const struct {
    std::string args, expected;
  } cases[] = {
      {"info texture.toml",
       "materials.wall.texture: texture file 'pipe.png' is not a regular file"},
      {"info sky.toml", "'pipe.png' is not a regular file"},
      {"info image.gltf", "images[0].uri: 'pipe.png' is not a regular file"},
      {"compare pipe.png pipe.png", "pipe.png: cannot read image: is not a regular file"},
  };
  for (const auto& c : cases) {
    const auto start = std::chrono::steady_clock::now();
    const std::string text = run_failing_cli(c.args, dir, "timeout 20 ");
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_LT(seconds, 5.0) << c.args;
    EXPECT_THAT(text, HasSubstr(c.expected)) << c.args;
    EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1) << text;
  }
}

TEST(BadInput, CliInfoOnABrokenSceneExitsNonZeroWithOneLine) {
  const fs::path dir = test_dir();
  const std::string scene =
      write_file(dir, "scene.toml", kLight + "[materials.wall]\nreflectance = 2\n");
  const std::string text = run_failing_cli("info '" + scene + "'", dir);
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1) << text;
  EXPECT_THAT(text, HasSubstr("lightbake: error: " + scene +
                              ":11:15: "
                              "materials.wall.reflectance: reflectance (2, 2, 2) is "
                              "outside [0, 1]"));
  std::ifstream out(dir / "out.txt");
  EXPECT_EQ(out.peek(), std::ifstream::traits_type::eof()) << "nothing printed on failure";
}

TEST(BadInput, CliBakeRefusesAbsurdRayCountsAndWritesNothing) {
  const fs::path dir = test_dir();
  const std::string scene = std::string(LIGHTBAKE_SOURCE_DIR) + "/scenes/room.toml";
  const fs::path out = dir / "bake_out";
  fs::remove_all(out);
  const std::string text = run_failing_cli(
      "bake '" + scene + "' -o '" + out.string() + "' --rays-per-zone-side 1000000", dir);
  EXPECT_THAT(text, HasSubstr("--rays-per-zone-side"));
  EXPECT_THAT(text, HasSubstr("1000000"));
  EXPECT_FALSE(fs::exists(out)) << "nothing written";
}

// ---- Hostile input (issue 13) -----------------------------------------------------------------

// `levels` definitions, each placing the one below `copies` times; the lowest is a quad.
std::string instance_tower(int levels, int copies) {
  std::string toml = kLight + "[[define.d0]]\nshape = \"quad\"\n";
  for (int level = 1; level < levels; ++level)
    for (int copy = 0; copy < copies; ++copy)
      toml += "[[define.d" + std::to_string(level) + "]]\ninstance = \"d" +
              std::to_string(level - 1) + "\"\ntranslate = [" + std::to_string(copy) + ", 0, 0]\n";
  return toml + "[[objects]]\ninstance = \"d" + std::to_string(levels - 1) + "\"\n";
}

TEST(BadInput, InstanceFanOutIsCountedBeforeExpanding) {
  // Before: 10 levels of 10 copies grew without end.
  const fs::path dir = test_dir();
  const std::string message = load_error_text(instance_tower(11, 10), dir);
  // d0 places 1 quad, each level 10 x (the instance + what it places): 21111111110 in all.
  EXPECT_THAT(message, HasSubstr("objects[1].instance: definition 'd10' places 21111111110 "
                                 "objects and instances; with the 1 before it that exceeds "
                                 "200000"));
  // Empty definitions are as much work: ten levels of ten instances of nothing.
  std::string empty = kLight + "define.d0 = []\n";
  for (int level = 1; level < 11; ++level)
    for (int copy = 0; copy < 10; ++copy)
      empty += "[[define.d" + std::to_string(level) + "]]\ninstance = \"d" +
               std::to_string(level - 1) + "\"\n";
  EXPECT_THAT(load_error_text(empty + "[[objects]]\ninstance = \"d10\"\n", dir),
              HasSubstr("definition 'd10' places 11111111110 objects and instances"));
}

TEST(BadInput, DeepInstanceChainIsNotACycle) {
  // Before: a 17-deep chain was "places itself (a cycle)". 64 levels load; 65 are too deep.
  const fs::path dir = test_dir();
  const LoadResult loaded = load_scene(write_file(dir, "scene.toml", instance_tower(64, 1)));
  ASSERT_EQ(loaded.scene.meshes.size(), 2u);  // the lamp and the quad at the bottom
  const std::string message = load_error_text(instance_tower(65, 1), dir);
  EXPECT_THAT(message, HasSubstr("define.d1[0].instance: instances nested deeper than 64 levels"));
  EXPECT_THAT(message, Not(HasSubstr("cycle")));
}

TEST(BadInput, ObjCoordinateOutOfRangeNamesTheLine) {
  // Before: reported as "index out of range".
  const fs::path dir = test_dir();
  write_file(dir, "tri.obj", "v 0 0 0\nv 1e39 0 0\nv 0 1 0\nf 1 2 3\n");
  const std::string message = load_error_text(mesh_object("tri.obj"), dir);
  EXPECT_THAT(message, HasSubstr(at_line(dir, mesh_key_line())));
  EXPECT_THAT(message, HasSubstr("tri.obj:2: vertex coordinate '1e39' is out of range"));
}

TEST(BadInput, ObjShortVertexLineNamesTheLine) {
  // Found by fuzz_obj: OpenMesh skipped "v 0 1" and wrote texture coordinates past its vertex
  // array (heap-buffer-overflow) for the face that used it.
  const fs::path dir = test_dir();
  write_file(dir, "tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1\nvt 0 0\nf 1/1 2/1 3/1\n");
  EXPECT_THAT(load_error_text(mesh_object("tri.obj"), dir),
              HasSubstr("tri.obj:3: vertex coordinates: found 2, need 3"));
  write_file(dir, "tri.obj", std::string("v 0 0 0\nv 1 0 0\nv 0 1\0J 0\nf 1 2 3\n", 34));
  EXPECT_THAT(load_error_text(mesh_object("tri.obj"), dir),
              HasSubstr("tri.obj:3: vertex coordinate '1"));
}

TEST(BadInput, PlyHeaderWithoutEndNamesTheLastLine) {
  // Found by fuzz_ply: OpenMesh's reader looped forever looking for end_header.
  const fs::path dir = test_dir();
  write_file(dir, "part.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n");
  EXPECT_THAT(load_error_text(mesh_object("part.ply"), dir),
              HasSubstr("part.ply:4: the header has no end_header line"));
  // Also found by fuzz_ply: a property before any element crashed OpenMesh (SEGV).
  write_file(dir, "part.ply",
             "ply\nformat ascii 1.0\nele?ent vertex 3\nproperty float x\nend_header\n");
  EXPECT_THAT(load_error_text(mesh_object("part.ply"), dir),
              HasSubstr("part.ply:3: unexpected 'ele?ent' in the PLY header"));
  // And a version other than 1.0 sent it into an endless loop of error messages.
  write_file(dir, "part.ply", "ply\nformat ascii \xb4.0\nelement vertex 0\nend_header\n");
  EXPECT_THAT(load_error_text(mesh_object("part.ply"), dir),
              HasSubstr("part.ply:2: PLY version '\xb4.0' (only 1.0 exists)"));
  // And a vertical tab, which ends a word for OpenMesh but not a line for getline.
  write_file(dir, "part.ply", "ply\nformat ascii 1.0\velement vertex 0\nend_header\n");
  EXPECT_THAT(load_error_text(mesh_object("part.ply"), dir),
              HasSubstr("part.ply:2: 'format' line with 6 words, expected 3"));
  write_file(dir, "part.ply", "ply\nformat ascii 1.0\nproperty float x\nend_header\n");
  EXPECT_THAT(load_error_text(mesh_object("part.ply"), dir),
              HasSubstr("part.ply:3: a property before any element"));
}

TEST(BadInput, ObjTextureIndexPastTheEndNamesTheLine) {
  const fs::path dir = test_dir();
  write_file(dir, "tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nf 1/1 2/2 3/3\n");
  const std::string message = load_error_text(mesh_object("tri.obj"), dir);
  EXPECT_THAT(message,
              HasSubstr("tri.obj:6: face texture coordinate index 3 out of range (2 vt so far)"));
}

TEST(BadInput, ObjPolygonWithTwoHundredThousandCornersIsRefusedQuickly) {
  // Before: ran for minutes.
  const fs::path dir = test_dir();
  std::ostringstream obj, face;
  constexpr int kCorners = 200000;
  face << "f";
  for (int i = 0; i < kCorners; ++i) {
    const double angle = 2.0 * 3.14159265358979 * i / kCorners;
    obj << "v " << std::cos(angle) << " " << std::sin(angle) << " 0\n";
    face << " " << i + 1;
  }
  write_file(dir, "disc.obj", obj.str() + face.str() + "\n");
  const auto start = std::chrono::steady_clock::now();
  const std::string message = load_error_text(mesh_object("disc.obj"), dir);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_THAT(message, HasSubstr("disc.obj:200001: face has more than 10000 vertices"));
  EXPECT_LT(seconds, 5.0);
}

// Before: a sparse 3 GB .obj (no line break) was read into one string, 2.1-9 GB and 14-120 s
// before "no triangles". Now the first line over 16 MiB stops it.
TEST(BadInput, ObjWithoutLineBreaksIsRefusedAtOnce) {
  const fs::path dir = test_dir();
  const std::string sparse = write_file(dir, "sparse.obj", "");
  fs::resize_file(sparse, uintmax_t(3) << 30);  // 3 GB of zeros, no disk blocks
  const auto start = std::chrono::steady_clock::now();
  const std::string message = load_error_text(mesh_object("sparse.obj"), dir);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  fs::remove(sparse);
  EXPECT_THAT(message, HasSubstr("sparse.obj:1: line longer than 16 MiB"));
  EXPECT_LT(seconds, 5.0);
}

TEST(BadInput, PlyNegativeAndHugeElementCountsNameTheHeaderLine) {
  // Before: bad_alloc.
  const fs::path dir = test_dir();
  const std::string tail =
      "property float x\nproperty float y\nproperty float z\nelement face 1\n"
      "property list uchar int vertex_indices\nend_header\n";
  for (const char* format : {"ascii", "binary_little_endian"}) {
    const std::string head = std::string("ply\nformat ") + format + " 1.0\n";
    write_file(dir, "part.ply", head + "element vertex -5\n" + tail);
    EXPECT_THAT(load_error_text(mesh_object("part.ply"), dir),
                HasSubstr("part.ply:3: element 'vertex' count -5 is negative"));
    write_file(dir, "part.ply", head + "element vertex 4000000000\n" + tail);
    EXPECT_THAT(load_error_text(mesh_object("part.ply"), dir),
                HasSubstr("part.ply:3: element 'vertex' count 4000000000 is more than the file's"));
  }
}

// A PNG chunk: length, type, data, CRC-32 of type and data (ISO 3309, as PNG requires).
std::string png_chunk(const char* type, const std::string& data) {
  std::string out;
  auto append_be32 = [&](uint32_t v) {
    for (int shift = 24; shift >= 0; shift -= 8) out.push_back(char((v >> shift) & 0xff));
  };
  append_be32(uint32_t(data.size()));
  out.append(type, 4);
  out.append(data);
  uint32_t crc = 0xffffffffu;
  for (size_t i = 4; i < out.size(); ++i) {  // over the type and the data
    crc ^= uint8_t(out[i]);
    for (int bit = 0; bit < 8; ++bit) crc = (crc >> 1) ^ (0xedb88320u & (0u - (crc & 1u)));
  }
  append_be32(~crc);
  return out;
}

TEST(BadInput, TextureClaimingTenGigapixelsNamesItsSize) {
  // Before: a bare std::bad_alloc. The header is read, the pixels never allocated.
  const fs::path dir = test_dir();
  // Width and height 100000 (0x000186a0), 8-bit RGB.
  const char header[13] = {0,          1, char(0x86), char(0xa0), 0, 1, char(0x86),
                           char(0xa0), 8, 2,          0,          0, 0};
  std::string png("\x89PNG\r\n\x1a\n", 8);
  png.append(png_chunk("IHDR", std::string(header, sizeof header)));
  png.append(png_chunk("IDAT", ""));
  png.append(png_chunk("IEND", ""));
  write_file(dir, "huge.png", png);
  const std::string message =
      load_error_text(kLight + "[materials.wall]\ntexture = \"huge.png\"\n", dir);
  EXPECT_THAT(message, HasSubstr(at_line(dir, 11) + "11: materials.wall.texture"));
  EXPECT_THAT(message,
              HasSubstr("huge.png': 100000 x 100000 x 3 values, more than the 1073741824"));
}

TEST(BadInput, CliAllowOutsideUrisIsOfferedByEverySceneCommand) {
  const fs::path dir = test_dir();
  for (const char* command : {"info", "bake", "render", "snapshot", "view"}) {
    const std::string binary = std::string(LIGHTBAKE_BINARY_DIR) + "/app/lightbake";
    const std::string help = (dir / "help.txt").string();
    const int status =
        std::system(("'" + binary + "' " + command + " --help > '" + help + "' 2>&1").c_str());
    EXPECT_EQ(WEXITSTATUS(status), 0) << command;
    std::stringstream text;
    text << std::ifstream(help).rdbuf();
    EXPECT_THAT(text.str(), HasSubstr("--allow-outside-uris")) << command;
  }
}

TEST(BadInput, TomlNestingIsBoundedByTheParser) {
  // toml++ refuses more than 256 nested values (TOML_MAX_NESTED_VALUES) with the place.
  const fs::path dir = test_dir();
  const std::string message =
      load_error_text("a = " + std::string(200000, '[') + std::string(200000, ']') + "\n", dir);
  EXPECT_THAT(message, HasSubstr(at_line(dir, 1) + "261: TOML syntax error"));
  EXPECT_THAT(message, HasSubstr("exceeded maximum nested value depth of 256"));
}

TEST(BadInput, CliRefusesAGltfUriOutsideTheFolderUnlessAllowed) {
  const fs::path dir = test_dir();
  fs::create_directories(dir / "scene");
  const float positions[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  write_file(dir, "outside.bin", std::string(reinterpret_cast<const char*>(positions), 36));
  const std::string scene = write_file(dir / "scene", "scene.gltf", R"({
    "asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
    "buffers": [{"byteLength": 36, "uri": "../outside.bin"}],
    "bufferViews": [{"buffer": 0, "byteLength": 36}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}]})");
  const std::string text = run_failing_cli("info '" + scene + "'", dir);
  EXPECT_THAT(text, HasSubstr("lightbake: error: " + scene +
                              ": at buffers[0].uri: '../outside.bin' points outside the scene's "
                              "folder"));
  const std::string binary = std::string(LIGHTBAKE_BINARY_DIR) + "/app/lightbake";
  const int status = std::system(
      ("'" + binary + "' info --allow-outside-uris '" + scene + "' > /dev/null 2>&1").c_str());
  EXPECT_EQ(WEXITSTATUS(status), 0) << "--allow-outside-uris reads it";
}

}  // namespace
}  // namespace lb
