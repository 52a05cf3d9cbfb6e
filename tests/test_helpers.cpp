#include "test_helpers.h"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <glm/gtc/constants.hpp>
#include <iterator>

namespace lb::test {

int add_material(Scene& scene, Material material) {
  scene.materials.push_back(std::move(material));
  return int(scene.materials.size()) - 1;
}

void add_flat_normal_map(Scene& scene, int material) {
  Texture map;
  map.width = map.height = 1;
  map.channels = 3;
  map.texels = {0.5f, 0.5f, 1.0f};
  scene.textures.push_back(map);
  scene.materials.at(size_t(material)).bump = BumpKind::normal_map;
  scene.materials.at(size_t(material)).bump_texture = int(scene.textures.size()) - 1;
}

std::pair<int, int> add_white_and_light(Scene& scene, float reflectance, float radiance) {
  Material white;
  white.name = "white";
  white.reflectance = vec3(reflectance);
  Material light = white;
  light.name = "light";
  light.emission = vec3(radiance);
  return {add_material(scene, white), add_material(scene, light)};
}

Scene make_partitioned_house() {
  Scene scene;
  const auto [w, l] = add_white_and_light(scene, 0.75f, 10.0f);
  scene.meshes.push_back(make_box({0, 0, 0}, {4, 3, 2}, w, true, "house"));
  scene.meshes.push_back(make_box({2.0f, 0, 0}, {2.001f, 3, 2}, w, false, "wall"));
  scene.meshes.push_back(make_quad({0.6f, 2.99f, 0.6f}, {0.8f, 0, 0}, {0, 0, 0.8f}, l, "light"));
  return scene;
}

Mesh make_quad(vec3 origin, vec3 edge_u, vec3 edge_v, int material, std::string name) {
  Mesh mesh;
  mesh.name = std::move(name);
  mesh.material = material;
  mesh.positions = {origin, origin + edge_u, origin + edge_u + edge_v, origin + edge_v};
  const vec3 n = glm::normalize(glm::cross(edge_u, edge_v));
  mesh.normals.assign(4, n);
  mesh.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  return mesh;
}

Texture make_rgb_texture(int width, int height, const std::function<vec3(int, int)>& colour,
                         std::string path) {
  Texture texture;
  texture.path = std::move(path);
  texture.width = width;
  texture.height = height;
  texture.channels = 3;
  for (int row = 0; row < height; ++row)
    for (int column = 0; column < width; ++column) {
      const vec3 c = colour(column, row);
      texture.texels.insert(texture.texels.end(), {c.r, c.g, c.b});
    }
  return texture;
}

static void append(Mesh& dst, const Mesh& src) {
  const uint32_t base = uint32_t(dst.positions.size());
  dst.positions.insert(dst.positions.end(), src.positions.begin(), src.positions.end());
  dst.normals.insert(dst.normals.end(), src.normals.begin(), src.normals.end());
  dst.uvs.insert(dst.uvs.end(), src.uvs.begin(), src.uvs.end());
  for (uvec3 t : src.triangles) dst.triangles.push_back(t + uvec3(base));
}

Mesh make_box(vec3 lo, vec3 hi, int material, bool inward, std::string name) {
  Mesh box;
  box.name = std::move(name);
  box.material = material;
  const vec3 d = hi - lo;
  const vec3 x(d.x, 0, 0), y(0, d.y, 0), z(0, 0, d.z);
  // Six outward-facing quads; swapping the edges flips a quad inward.
  struct Face {
    vec3 origin, u, v;
  };
  const Face faces[6] = {
      {lo, y, x}, {lo + z, x, y},  // -z, +z
      {lo, z, y}, {lo + x, y, z},  // -x, +x
      {lo, x, z}, {lo + y, z, x},  // -y, +y
  };
  for (const Face& f : faces)
    append(box, inward ? make_quad(f.origin, f.v, f.u, material)
                       : make_quad(f.origin, f.u, f.v, material));
  return box;
}

Mesh make_sphere(vec3 centre, float radius, int rings, int segments, int material, bool inward,
                 std::string name) {
  Mesh mesh;
  mesh.name = std::move(name);
  mesh.material = material;
  for (int r = 0; r <= rings; ++r) {
    const float theta = glm::pi<float>() * float(r) / float(rings);
    for (int s = 0; s <= segments; ++s) {
      const float phi = 2.0f * glm::pi<float>() * float(s) / float(segments);
      const vec3 n(std::sin(theta) * std::cos(phi), std::cos(theta),
                   std::sin(theta) * std::sin(phi));
      mesh.positions.push_back(centre + radius * n);
      mesh.normals.push_back(inward ? -n : n);
      mesh.uvs.push_back({float(s) / float(segments), float(r) / float(rings)});
    }
  }
  const uint32_t row = uint32_t(segments + 1);
  for (uint32_t r = 0; r < uint32_t(rings); ++r)
    for (uint32_t s = 0; s < uint32_t(segments); ++s) {
      const uint32_t a = r * row + s, b = a + row, c = b + 1, d = a + 1;
      // Outward winding is (a, d, b), (d, c, b) for this parametrisation.
      uvec3 t1 = inward ? uvec3(a, b, d) : uvec3(a, d, b);
      uvec3 t2 = inward ? uvec3(d, b, c) : uvec3(d, c, b);
      if (r != 0) mesh.triangles.push_back(t1);
      if (r + 1 != uint32_t(rings)) mesh.triangles.push_back(t2);
    }
  return mesh;
}

// E = L/2 * sum_i angle_i * (n . unit(v_i x v_i+1)) over the clipped polygon, with the sign
// that makes it >= 0.
Scene make_masked_leaf_scene(float sun) {
  Scene scene;
  Texture alpha;
  alpha.path = "checker alpha";
  alpha.width = alpha.height = 8;
  alpha.channels = 1;
  for (int row = 0; row < 8; ++row)
    for (int column = 0; column < 8; ++column) alpha.texels.push_back(float((row + column) % 2));
  scene.textures.push_back(alpha);
  Material floor, leaf;
  floor.reflectance = vec3(0.5f);
  leaf.reflectance = vec3(0.3f);
  leaf.alpha_mask = true;
  leaf.alpha_cutoff = 0.5f;
  leaf.alpha_texture = 0;
  const int f = add_material(scene, floor), l = add_material(scene, leaf);
  scene.meshes.push_back(make_quad({-2, 0, 2}, {4, 0, 0}, {0, 0, -4}, f, "floor"));
  scene.meshes.push_back(make_quad({-0.5f, 0.5f, 0.5f}, {1, 0, 0}, {0, 0, -1}, l, "leaf"));
  Lamp lamp;
  lamp.kind = LampKind::directional;
  lamp.direction = {0, -1, 0};
  lamp.intensity = vec3(sun);
  scene.lights.push_back(lamp);
  return scene;
}

TwoSidedPanel make_two_sided_panel(float size, float radiance, float height,
                                   float floor_reflectance, bool two_sided) {
  TwoSidedPanel out;
  Material panel;
  panel.reflectance = vec3(0.0f);
  panel.emission = vec3(radiance);
  panel.two_sided_emission = two_sided;
  Material floor;
  floor.reflectance = vec3(floor_reflectance);
  const int p = add_material(out.scene, panel), f = add_material(out.scene, floor);
  const float h = 0.5f * size;
  out.scene.meshes.push_back(make_quad({-h, 0, -h}, {size, 0, 0}, {0, 0, size}, p, "panel"));
  out.scene.meshes.push_back(make_quad({-1, -height, 1}, {2, 0, 0}, {0, 0, -2}, f, "floor"));
  out.scene.meshes.push_back(
      make_quad({-1, height, -1}, {2, 0, 0}, {0, 0, 2}, f, "ceiling floor"));
  out.corners = {{-h, 0, -h}, {h, 0, -h}, {h, 0, h}, {-h, 0, h}};
  return out;
}

double polygon_irradiance(const std::vector<glm::dvec3>& polygon, glm::dvec3 p, glm::dvec3 n,
                          double radiance) {
  std::vector<glm::dvec3> clipped;
  for (size_t k = 0; k < polygon.size(); ++k) {
    const glm::dvec3 a = polygon[k], b = polygon[(k + 1) % polygon.size()];
    const double da = glm::dot(a - p, n), db = glm::dot(b - p, n);
    if (da >= 0) clipped.push_back(a);
    if ((da > 0 && db < 0) || (da < 0 && db > 0)) clipped.push_back(a + (b - a) * (da / (da - db)));
  }
  double sum = 0.0;
  for (size_t k = 0; k < clipped.size(); ++k) {
    const glm::dvec3 a = glm::normalize(clipped[k] - p);
    const glm::dvec3 b = glm::normalize(clipped[(k + 1) % clipped.size()] - p);
    const glm::dvec3 c = glm::cross(a, b);
    const double length = glm::length(c);
    if (length < 1e-15) continue;
    sum += std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0)) * glm::dot(n, c / length);
  }
  return 0.5 * radiance * std::abs(sum);
}

std::string source_dir() {
  return LIGHTBAKE_SOURCE_DIR;
}

std::string fresh_dir(const std::string& area, const std::string& name) {
  const std::filesystem::path dir = std::filesystem::path(output_dir()) / area / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

namespace {
std::string read_whole(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}
}  // namespace

std::string read_bytes(const std::string& path) {
  return read_whole(path);
}

CliRun run_lightbake(const std::string& args, const std::string& cwd) {
  // Appended, not "'" + std::string: GCC 12's -Wrestrict misfires on that at -O3, for some
  // lengths of the build path only (a clean clone in /tmp/ci failed where /work/main did not).
  std::string command = "'";
  command.append(LIGHTBAKE_BINARY_DIR).append("/app/lightbake' ").append(args);
  return run_command(command, cwd);
}

CliRun run_command(const std::string& command_line, const std::string& cwd) {
  static std::atomic<int> counter{0};
  const std::filesystem::path logs = std::filesystem::path(output_dir()) / "cli";
  std::filesystem::create_directories(logs);
  const std::string stem =
      (logs / ("run-" + std::to_string(::getpid()) + "-" + std::to_string(counter++))).string();
  std::string command = "cd '";
  command.append(cwd).append("' && ").append(command_line);
  command.append(" > '").append(stem).append(".out' 2> '").append(stem).append(".err'");
  const int status = std::system(command.c_str());
  CliRun run;
  run.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  run.out = read_whole(stem + ".out");
  run.err = read_whole(stem + ".err");
  return run;
}

std::string output_dir() {
  std::filesystem::create_directories(LIGHTBAKE_TEST_OUTPUT_DIR);
  return LIGHTBAKE_TEST_OUTPUT_DIR;
}

std::string xvfb_lightbake_command(const std::string& args) {
  std::string command = "'";
  command.append(LIGHTBAKE_BINARY_DIR).append("/app/lightbake' ").append(args);
  return xvfb_command(command);
}

std::string xvfb_command(const std::string& command_line) {
  // xvfb-run -a takes the first free display from -n on; tests run in parallel (ctest -j)
  // would race for the same one, so each process starts its search somewhere else.
  const int first_display = 100 + int(::getpid() % 5000);
  // Our own X authority file (-f): without one xvfb-run makes a temporary folder and, when the
  // command exits within moments of the server starting, may fail to remove it and exit 5
  // instead of the command's status (seen in CI).
  static std::atomic<int> counter{0};
  const std::filesystem::path folder = std::filesystem::path(output_dir()) / "xvfb";
  std::filesystem::create_directories(folder);
  const std::string auth =
      (folder / ("auth-" + std::to_string(::getpid()) + "-" + std::to_string(counter++))).string();
  std::string command = "ASAN_OPTIONS=detect_leaks=0 xvfb-run -a -n ";
  command.append(std::to_string(first_display)).append(" -f '").append(auth);
  command.append("' -s '-screen 0 800x600x24' ").append(command_line);
  return command;
}

}  // namespace lb::test
