#pragma once
// The coarse radiosity mesh: each diffuse scene mesh refined to the patch size and its
// triangles grouped into patches (Shirley 1990 sec. 3.2: "a very coarse environment
// partitioning can be used"). Built with OpenMesh, independent of the illumination maps.
//
// How a mesh becomes patches (patch edge h, target patch area h^2):
//  1. Crease split: a vertex whose triangles disagree by more than the crease angle (30 deg)
//     is duplicated per smooth group, so no vertex colour is shared across a crease.
//  2. Refinement: every edge longer than sqrt(2) h is bisected, longest first (Rivara's
//     longest-edge bisection, OpenMesh edge splits). The split decision depends only on the
//     edge's two end positions and the midpoint is (a + b) / 2, so an edge duplicated at a UV
//     seam or a crease is split identically on both sides: the result is conforming (no
//     T-junctions, no cracks) even across vertex seams. All vertex attributes are interpolated.
//  3. Grouping: triangles are grown into patches breadth-first across shared edges, in
//     triangle order, until a patch reaches h^2; a triangle joins only if its normal is within
//     the crease angle of the patch's first triangle and of its neighbour, so patches never
//     cross a crease. A mesh has one material, so patches never cross a material boundary.
//     Left-over slivers below 0.3 h^2 merge into their smallest compatible neighbour.
//
// Automatic patch size: h = sqrt(F / 256), F the area of the largest face of the scene's
// bounding box (the two largest extents), i.e. about 16 x 16 patches on the largest wall. The
// paper's 32 patches per wall left the soft light 4.5% off the reference renderer on
// room_two_blocks (docs/radiosity.md: patch size against error); 256 brings it to 0.7% for
// 0.9 CPU s of bake. Capped at 0.5 m (kMaxAutomaticPatchSize): soft light changes at the
// scale of furniture, not of the building, so a 74 m level gets 0.5 m patches, not 4.6 m ones
// (one a room wall); the bundled scenes are all below the cap (cornell 0.125 m, room 0.25 m).
// A mesh's own `bake.patch_size` takes precedence over everything.

#include <cstdint>
#include <vector>

#include "bake/progress.h"
#include "bake/scene.h"

namespace lb {

inline constexpr float kCreaseAngleDegrees = 30.0f;
inline constexpr float kMaxAutomaticPatchSize = 0.5f;  // m (architectural scale, see above)

struct Patch {
  uint32_t mesh = 0;                // scene mesh
  std::vector<uint32_t> triangles;  // triangles of the refined mesh
  std::vector<float> triangle_cdf;  // cumulative area fraction over `triangles`, last = 1
  double area = 0.0;                // m^2
  vec3 normal{0.0f};                // area-weighted mean geometric normal, unit
  bool covered = false;             // inside other geometry (contact_cuts.h): never seen
};

struct PatchMesh {
  Mesh mesh;                             // refined scene mesh; empty when it has no patches
  std::vector<uint32_t> triangle_patch;  // per refined triangle, global patch id
};

// CPU seconds of build_patches' steps (this thread's clock), for profiling (issue 16).
struct PatchBuildSeconds {
  double refine = 0.0;    // steps 1-2: crease split and refinement
  double cuts = 0.0;      // contact cuts (contact_cuts.h, step 1)
  double coverage = 0.0;  // coverage probes (contact_cuts.h, step 2)
  double grouping = 0.0;  // step 3 and the patch records
};

struct Patches {
  std::vector<Patch> patches;
  std::vector<PatchMesh> meshes;  // per scene mesh
  float default_patch_size = 0.0f;
  PatchBuildSeconds seconds;
};

// min(sqrt(largest bounding-box face / 256), 0.5 m); 0.5 m for an empty scene.
float automatic_patch_size(const Scene& scene);

// Step 1 above: duplicates vertices at creases (> crease angle). Same surface.
Mesh split_creases(const Mesh& mesh, float crease_degrees = kCreaseAngleDegrees);

// Step 2 above: bisects edges longer than `max_edge`, longest first, conforming.
// Drops zero-area triangles.
Mesh refine_mesh(const Mesh& mesh, float max_edge);

// About how many patches build_patches will make (each mesh's area over its h^2, at least one
// a triangle), computed in a pass over the triangles: checked before the patches are built.
double estimate_patch_count(const Scene& scene, float patch_size, bool include_emitters);

// Steps 1-3 for every diffuse mesh (and emitting diffuse meshes when `include_emitters`),
// with the contact cuts and coverage of contact_cuts.h between steps 2 and 3 (grouping never
// mixes covered and open triangles). `patch_size` <= 0 means automatic. `accel` traces
// `scene` (for the coverage probes); null builds one. `contact_cuts` false skips both (to
// measure what they fix). `progress` (may be null) gets "radiosity: patches" with the share
// of the meshes' triangles done, and stops the work between meshes when cancelled.
class Accel;
Patches build_patches(const Scene& scene, float patch_size, bool include_emitters,
                      const Accel* accel = nullptr, bool contact_cuts = true,
                      const Progress* progress = nullptr);

// Patch radiance to vertex radiance (Cohen and Greenberg 1985): each vertex takes the
// area-weighted mean of the distinct open patches around its position (covered ones only when
// it has no open one, so contact lines are not darkened), counting only triangles
// within the crease angle of the vertex's own triangles (no bleeding across creases; vertices
// duplicated at UV seams agree). `patch_radiance` is indexed by global patch id.
std::vector<vec3> vertex_radiance_from_patches(const PatchMesh& patch_mesh,
                                               const std::vector<Patch>& patches,
                                               const std::vector<vec3>& patch_radiance);

}  // namespace lb
