#pragma once
// Tangents for tangent-space normal maps in the MikkTSpace convention (M. Mikkelsen, "Simulation
// of wrinkled surfaces revisited", MSc thesis, Copenhagen 2008): the frame Blender bakes normal
// maps in and glTF prescribes for files without TANGENT. Written from the thesis and the
// reference implementation's description:
//  - per triangle, the directions of dP/du and dP/dv, and the triangle's UV orientation (does
//    the UV triangle keep the winding of the 3D one, in the map's frame where v points up?);
//  - per corner, dP/du projected into the plane of the corner's normal, weighted by the corner's
//    angle (between its two edges, projected into that plane);
//  - summed over the corners that share a vertex (same position, normal and uv: welded by value,
//    not by index) and the same UV orientation, then normalised; w = +1 for orientation-keeping
//    UVs, -1 for mirrored ones;
//  - triangles with degenerate UVs take the tangent of another group at the same vertex.
// Simplification: corners of one vertex with one orientation form one group even when their
// triangles do not share edges (the reference splits such fans; manifold meshes do not have
// them), and, as the reference's default (180 degree threshold), groups are never split by angle.

#include "bake/scene.h"

namespace lb {

// Fills `mesh.tangents` (xyz unit, w = handedness) from `uvs` (glTF convention, v down the
// image) and `normals` (flat geometric normals when empty). A vertex whose corners get
// different tangents (a mirror seam, a flat-shaded mesh) is split with append_vertex_copy.
// No-op without uvs.
void generate_mikktspace_tangents(Mesh& mesh);

}  // namespace lb
