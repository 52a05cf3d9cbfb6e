#pragma once
// Seams stitched (issue 36; the method of Iwanicki, "Lighting technology of The Last of Us",
// SIGGRAPH 2013). Where two charts meet, in one mesh or between meshes that touch (a floor in
// pieces, modular tiles, a sphere's charts), an engine reads each side with bilinear filtering
// from different texels, and the two reads disagree: a visible line.
//
// Seams: pairs of triangle edges with the same two end points in space (to a tolerance) but
// other lightmap UVs, whose triangles face the same way (within kSeamMaxAngleDeg: a crease such
// as a wall meeting the floor is no seam, its light really differs) and are not hidden inside
// other geometry (Mesh::hidden). Along each, samples at kSeamSamplesPerTexel per texel of the
// longer side; each asks that the two sides' bilinear reads agree.
//
// Stitching: the texels the samples read are moved by least squares,
//     minimise  sum_samples w (read_A(x) - read_B(x))^2 + sum_texels (x - x0)^2,
// with the reads linear in x: (I + w A^T A) x = x0, solved per channel by conjugate gradients
// (symmetric positive definite), under x >= 0: channels that go below 0 are held there and the
// rest solved again (where a seam runs along a shadow's edge, clamping afterwards instead left
// the sides 20-35% apart). w (`seam_weight`) sets how far the seam wins over keeping the
// baked values: the residual jump falls about as 1 / (1 + w k), k the samples a texel takes
// part in. Texels no sample reads keep their bits; the same input gives the same bits.

#include <array>
#include <cstddef>
#include <vector>

#include "bake/bake_result.h"
#include "bake/scene.h"

namespace lb {

inline constexpr float kSeamMaxAngleDeg = 30.0f;
inline constexpr float kSeamSamplesPerTexel = 3.0f;

struct SeamSample {
  std::array<size_t, 4> a{}, b{};       // texel nodes each side reads
  std::array<float, 4> wa{}, wb{};      // their bilinear weights
};

// The seams of `meshes` (each with lightmap_uvs into a width x height map, or none; `hidden`
// read where as long as the triangles). `tolerance`: metres within which end points coincide.
std::vector<SeamSample> find_seams(const std::vector<const Mesh*>& meshes, int width, int height,
                                   float tolerance);

// The seams of `scene`'s meshes charted in `maps`' atlas (mesh_with_lightmap), end points
// within the scene's contact tolerance.
std::vector<SeamSample> atlas_seams(const Scene& scene, const IlluminationMaps& maps);

struct StitchStats {
  size_t samples = 0;
  size_t texels = 0;          // texels moved
  double jump_before = 0.0;   // mean |read_A - read_B| over the samples and channels, W/(sr m^2)
  double jump_after = 0.0;
  int iterations = 0;
};

// Moves the texels the samples read, as above. `values`: width*height, E/pi.
StitchStats stitch_seams(const std::vector<SeamSample>& seams, std::vector<vec3>& values,
                         float seam_weight = 16.0f);

// A bilinear read of `values` at `uv`, clamped to the edge as a GPU's sampler (for tests and
// the measurement of seams).
vec3 bilinear_read(const std::vector<vec3>& values, int width, int height, vec2 uv);

}  // namespace lb
