#pragma once
// Environment captures for the specular surfaces that no planar pass shows.
//
// Curved mirrors, glass and glossy metal: one cube per object (a mesh, or meshes whose
// bounding boxes touch, e.g. a bottle and its stopper), captured at the object's own centre
// without the object, holding radiance (rgb) and the distance of what it sees from the centre
// (alpha, m). shaders/environment.glsl reads it with parallax correction: it follows the
// reflected or refracted ray from the shaded point to where it meets that captured surface
// and reads the cube in the direction of the hit (Szirmay-Kalos et al., "Approximate
// Ray-Tracing on the GPU with Distance Impostors", Eurographics 2005), so a ring's outer wall
// reflects the table where the ray really lands, not where the ray from the centre would.
// Without itself in the capture, a concave object misses its own inter-reflections (the
// ring's inner wall sees what lies beyond the opposite wall, not the wall): with itself, the
// distance lookup from its own surface would stop at once on the object.
//
// A glass object gets a second cube, of itself alone (normal and distance), so the refracted
// ray can find where it leaves the glass and refract out, and cross a hollow object's far
// wall (shaders/environment.glsl glass_crossing): refracting once and reading from the entry
// point, per-object cubes made Figure 7 worse (MRE 0.050 -> 0.057); through both surfaces
// they make it better (0.041).
//
// At most kMaxObjectCubes objects get a cube, the largest (bounding-box diagonal) first; the
// others, and planar mirrors or plates without a planar pass (beyond kMaxPlanarPasses, or
// rougher than kMaxPlanarRoughness) read one shared cube at the centre of all specular meshes,
// by direction only, with one refraction for glass: the capture of the viewer before
// per-object cubes, bit for bit.

#include <functional>
#include <vector>

#include "viewer/gl_resources.h"
#include "viewer/gpu_scene.h"

namespace lb {

// Cubes for curved specular objects, at most (each costs six 128^2 scene passes, 256^2 for
// mirrors, per scene change, twelve for glass; Figure 6's 8 leg cubes added ~0.15 s CPU to a
// snapshot on llvmpipe).
constexpr int kMaxObjectCubes = 8;

struct EnvironmentCube {
  gl::Texture texture;
  vec3 centre{0.0f};
  bool parallax = false;  // distance-corrected lookups (object cubes) or direction only (shared)
  int texels = 0;         // face size; log2 of it is the roughest mip level glossy metal reads
  // Glass objects: the object alone from the same centre (rgb 0.5 n + 0.5, alpha distance),
  // so a refracted ray can leave the glass; 0 for others.
  gl::Texture self;
  float size = 0.0f;  // m, the object's bounding-box diagonal
  std::vector<int> meshes;
};

class EnvironmentCubes {
 public:
  // Draws the scene without the meshes in `skip` for a capture (Renderer::draw_scene with
  // capture = true, then the sky), into the bound framebuffer; with `normals`, Term::normals.
  using DrawCapture = std::function<void(const glm::mat4& view_projection, vec3 eye,
                                         const std::vector<int>& skip, bool normals)>;

  EnvironmentCubes() = default;
  // Captures every cube `scene` needs (none without specular meshes).
  EnvironmentCubes(const GpuScene& scene, const DrawCapture& draw);

  bool empty() const { return cubes_.empty(); }
  // The cube mesh `mesh` reads, or null (diffuse meshes).
  const EnvironmentCube* cube_for(int mesh) const;
  int object_cube_count() const { return object_cubes_; }

 private:
  std::vector<EnvironmentCube> cubes_;
  std::vector<int> cube_of_mesh_;  // index into cubes_, -1 for none
  int object_cubes_ = 0;
};

}  // namespace lb
