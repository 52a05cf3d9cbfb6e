#pragma once
// Radiosity meshes that conform to where other geometry meets a surface (issue 11): a patch
// must not straddle an occluder, or the power it receives on one side is shot again from the
// other (light through a 1 mm wall) or from the part under a block (power that dies inside the
// block, and a radiance diluted by area nobody sees).
//
// Two steps, both after refinement (patches.h):
//  1. Contact cuts: every triangle is split along the plane of each triangle of *another* mesh
//     that crosses it and whose plane section actually meets that triangle (within a
//     tolerance, so a block standing exactly on the floor cuts the floor along its footprint).
//     The cut runs across the whole receiving triangle (at most a patch wide): exact along the
//     contact line, a harmless extra edge beyond it. Splitting an edge depends only on its two
//     end vertices and the plane, and is shared through a cache, so neighbours cut by the
//     same plane stay conforming; where a contact line ends inside a triangle its neighbour
//     is not cut (a T-junction on a flat surface, no gap wider than rounding).
//     Small cutters do not cut (issue 16): a cutter mesh is skipped when what it hides of the
//     receiving triangle's plane fits in a square of side `min_footprint` (build_patches:
//     h / 4) in the plane's axes, or when it only touches the plane at vertices or edges (a
//     bowl or a ball resting on a table hides nothing). The k facets of a thin leg cut each
//     receiving triangle into ~k^2 / 2 pieces (3.9M patches from 40k triangles on the
//     1M-triangle level). Bound: a skipped cutter hides less than (h / 4)^2 = h^2 / 16, 6.25%
//     of a patch of h^2; coverage (step 2) still marks whatever triangles end up covered, so
//     at most that share of a patch's power is shot from inside the cutter and lost. A block
//     as wide as a quarter patch, or a long thin wall, still cuts along its footprint.
//  2. Coverage: a triangle is *covered* when most of five short probes from its centroid (the
//     normal and four directions 60 degrees off it) first meet a back face of a closed mesh:
//     it lies inside closed geometry (under a block, inside an intersecting block, in a wall's
//     footprint). Patches never mix covered and open triangles, so no origin is shot from
//     inside geometry and the open area alone carries a patch's radiance; nor sheltered ones
//     (under an open sheet: covered_triangles below).
// Chosen over per-ray rejection of origins (a back-face hit is also a legal event in open
// scenes, and rejection does not stop a patch straddling a thin wall) and over full
// constrained retriangulation (much more code for the same patches on the planar, box-like
// contacts of architectural scenes). Curved contacts are cut by the planes of their facets.

#include <cstdint>
#include <vector>

#include "bake/accel.h"
#include "bake/box_grid.h"
#include "bake/scene.h"

namespace lb {

// Distance below which a point counts as on a plane: 1e-6 of the scene's largest extent
// (4 um in a 4 m room; a 1 mm wall is 250 of them).
float contact_tolerance(const Scene& scene);

// The bounds of the scene's meshes, indexed once for all the receivers' cuts.
BoxGrid mesh_box_grid(const Scene& scene);

// Hovering cutters (near contacts): a triangle of another mesh lying in front of the receiving
// triangle, facing along or against it (within 26 degrees) and no farther than `hover_gap`
// from its plane at any corner, hides what lies under it as a contact does (a lamp 1 cm under
// the ceiling, a cloth 1 mm above a table): the region under it gets little light, and a patch
// straddling its outline mixes that dark with the open side's light. The receiver is cut along
// the outline's edges (those no same-facing triangle of the cutter's mesh shares), each by the
// plane through the edge across the cutter's own plane; coverage then marks the part beneath
// (sheltered under an open sheet, covered inside a closed mesh).
// The footprint rule applies to what the mesh's hovering triangles hide, and an outline edge
// shorter than `min_footprint` does not cut: a curved outline (a ring's rim, 192 edges) would
// cut the receiver to slivers, and straight outlines (lamps, rugs, slabs) are what matter.
//
// Step 1 for `mesh`, the refined mesh of scene mesh `self`; every attribute is interpolated
// linearly (normals and tangents renormalised). Triangle order: each input triangle's pieces
// in place of it. `meshes` is mesh_box_grid(scene). Cutter meshes with a footprint below
// `min_footprint` (m, see above; 0 = all cut) are skipped. Cost: the triangles of the meshes
// whose bounds meet `mesh`'s, per triangle the cutters whose bounds meet it, and once per
// (cutter mesh, receiving plane) the cutter's triangles. Hovering cutters within `hover_gap`
// (m; 0 = none) cut along their outline.
Mesh cut_along_contacts(const Mesh& mesh, const Scene& scene, const BoxGrid& meshes, size_t self,
                        float tolerance, float min_footprint = 0.0f, float hover_gap = 0.0f);

// Per scene mesh, 1 when it bounds a volume: its triangles' vector areas (area times unit
// normal) cancel to within kClosedMeshTolerance of its area. Every closed surface's do (the
// divergence theorem), whatever its triangulation: the T-junctions the contact cuts leave and
// vertices that were never welded do not open it. An open sheet's sum is its area (a lamp's
// quad, a wall made of one quad, a room open at a window). A tube open at both ends passes too;
// its inside is dark enough (a pipe, a chimney).
inline constexpr double kClosedMeshTolerance = 1e-3;
std::vector<uint8_t> closed_meshes(const Scene& scene);

// Step 2: per triangle of `mesh`, kCovered when covered: inside other geometry (most probes
// meet a back face of a closed mesh; `closed` = closed_meshes(accel.scene())), or, where no sky
// lights the void, behind one-sided surfaces (probes meet back faces and the void, no front
// face, and no lamp reaches it: a block's side sunk below a floor). Such surface gets no light.
// A back face of an open sheet with no void beyond encloses nothing: surface where most probes
// meet one is kSheltered, lit through the gap round the sheet's edges (the ceiling 1 cm behind
// the Cornell box's one-sided lamp: Cycles finds 0.06-0.13 W/(sr m^2) at its edge; it held 0
// when sheets enclosed), seen and lit, but a radiosity patch never mixes it with open surface
// (one straddling a lamp's outline mixes the gap's dark with the lit ceiling beside it). Else
// kOpen. `accel` traces the whole scene; glass covers nothing (light passes through it).
enum TriangleCoverage : uint8_t { kOpen = 0, kCovered = 1, kSheltered = 2 };
std::vector<uint8_t> covered_triangles(const Mesh& mesh, const Accel& accel,
                                       const std::vector<uint8_t>& closed);

}  // namespace lb
