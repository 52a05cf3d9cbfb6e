#pragma once
// Small scenes built in code, so tests do not depend on the loaders.

#include <cstring>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "bake/scene.h"

namespace lb::test {

// Adds a material and returns its index.
int add_material(Scene& scene, Material material);

// Gives material `material` a one-texel normal map that leaves the normal as it is (n = n0):
// a bump-mapped surface (which takes directional bands) whose light is the flat one's.
void add_flat_normal_map(Scene& scene, int material);

// Adds a diffuse material "white" and an emitter "light" of the same reflectance, emitting
// `radiance` W/(sr m^2); returns their indices.
std::pair<int, int> add_white_and_light(Scene& scene, float reflectance, float radiance);

// A closed 4 x 3 x 2 m house (white, albedo 0.75) split at x = 2 by a 1 mm partition standing
// flush on its floor and against its walls and ceiling; a 0.8 m square light (10 W/(sr m^2))
// 1 cm under the ceiling on the x < 2 side. Meshes "house", "wall", "light".
Scene make_partitioned_house();

// A quad with corners `origin`, origin+edge_u, origin+edge_u+edge_v, origin+edge_v; its front
// faces along cross(edge_u, edge_v). Two triangles, per-vertex normals and UVs.
Mesh make_quad(vec3 origin, vec3 edge_u, vec3 edge_v, int material, std::string name = "quad");

// A linear RGB texture of width x height texels, texel (column, row) = colour(column, row),
// row 0 at the top (sky images, normal maps).
Texture make_rgb_texture(int width, int height, const std::function<vec3(int, int)>& colour,
                         std::string path = "test texture");

// An axis-aligned box seen from outside (normals out) or inside (normals in).
Mesh make_box(vec3 min, vec3 max, int material, bool inward, std::string name = "box");

// A UV sphere; `inward` flips it so its front faces the centre.
Mesh make_sphere(vec3 centre, float radius, int rings, int segments, int material, bool inward,
                 std::string name = "sphere");

// Irradiance E in W/m^2 at p (unit normal n) from a uniform Lambertian polygon of radiance L,
// clipped to p's horizon (Lambert's formula): the analytic reference for direct light.
double polygon_irradiance(const std::vector<glm::dvec3>& polygon, glm::dvec3 p, glm::dvec3 n,
                          double radiance);

// A double-sided emissive square (glTF doubleSided) between two floors: the square's corners
// (edge `size`, y = 0, centred on the y axis, front facing -y), black, radiance `radiance`;
// 2 x 2 m floors of albedo `floor_reflectance`, "ceiling floor" at y = +height facing down and
// "floor" at y = -height facing up. Both floors see one face: each gets Lambert's irradiance.
struct TwoSidedPanel {
  Scene scene;
  std::vector<glm::dvec3> corners;
};
TwoSidedPanel make_two_sided_panel(float size, float radiance, float height,
                                   float floor_reflectance, bool two_sided = true);

// glTF alphaMode MASK: a 1 x 1 m leaf (y = 0.5, over x, z in [-0.5, 0.5], albedo 0.3) whose
// alpha is an 8 x 8 checker of 0 and 1 (cutoff 0.5: bilinear filtering cuts exactly half its
// area), over a 4 x 4 m floor (y = 0, albedo 0.5), lit by a sun straight down of irradiance
// `sun` W/m^2.
Scene make_masked_leaf_scene(float sun);

std::string source_dir();
std::string output_dir();  // created on demand; failing image tests write here
// output_dir()/AREA/NAME, emptied and created: a test's own scratch folder.
std::string fresh_dir(const std::string& area, const std::string& name);

// Whether two arrays hold the same bits (empty ones included, without touching their data).
template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

// `lightbake ARGS` run through the shell (arguments quoted by the caller) from `cwd`, with its
// exit status and what it printed.
struct CliRun {
  int status = -1;  // exit status, or -1 when it did not exit normally
  std::string out;
  std::string err;
};
CliRun run_lightbake(const std::string& args, const std::string& cwd = ".");
// The same for any command line (e.g. an installed lightbake, or one under strace).
CliRun run_command(const std::string& command, const std::string& cwd = ".");

// A file's bytes ("" when it cannot be read).
std::string read_bytes(const std::string& path);

// The shell command that runs `lightbake ARGS` in a window under a fresh Xvfb display
// (800x600x24). Leak checking is off for it: under the sanitizer build, the GLX driver Mesa
// loads for the window leaks and is unloaded before exit, where no suppression can name it.
std::string xvfb_lightbake_command(const std::string& args);
// The same for any command line run under Xvfb (e.g. `sh script` that drives the window).
std::string xvfb_command(const std::string& command_line);

}  // namespace lb::test
