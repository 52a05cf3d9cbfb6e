#pragma once
// Procedural shapes and the mesh operations the loaders share (transforms, normals, tangents).
// Every shape is built in its own local frame with unit shading normals, UVs and
// counter-clockwise fronts facing outwards; `flip_mesh` turns one inside out (a closed room).
// UVs follow glTF: (0, 0) is the image's top-left texel, so v grows downwards on upright faces.

#include <array>
#include <glm/glm.hpp>
#include <vector>

#include "bake/scene.h"

namespace lb {

// A rectangle in the local XZ plane, centred on the origin, facing +Y. UVs span [0,1] unless
// `uv_tile` > 0, in which case one texture repeat covers `uv_tile` metres.
Mesh make_quad(vec2 size, float uv_tile = 0.0f);

// A parallelogram with corners origin, origin+edge_u, origin+edge_u+edge_v, origin+edge_v,
// facing along cross(edge_u, edge_v).
Mesh make_quad_corners(vec3 origin, vec3 edge_u, vec3 edge_v, float uv_tile = 0.0f);

// An axis-aligned box with flat faces (4 vertices per face), normals out.
Mesh make_box(vec3 min, vec3 max, float uv_tile = 0.0f);

// The six faces of `make_box` as separate meshes, in the order -X, +X, -Y, +Y, -Z, +Z.
std::array<Mesh, 6> make_box_faces(vec3 min, vec3 max, float uv_tile = 0.0f);

// A UV sphere centred on the origin; `rings` >= 2 from pole to pole, `segments` >= 3 around Y.
Mesh make_sphere(float radius, int rings, int segments);

// A cylinder around the Y axis from y = -height/2 to +height/2. With `inner_radius` > 0 it is a
// closed tube (outer wall, inner wall, two annular ends); otherwise `caps` closes it with discs.
Mesh make_cylinder(float radius, float inner_radius, float height, int segments, bool caps);

// A torus around the Y axis: `major_radius` to the tube centre, `minor_radius` of the tube.
Mesh make_torus(float major_radius, float minor_radius, int rings, int segments);

// A surface of revolution around the Y axis. `profile` holds (radius, height) points, walked
// with the outside on the right (bottom to top for an outer wall). With `thickness` > 0 an
// inner wall is added, offset inwards by `thickness` metres and walked back, so the result is
// a closed solid shell (a bottle). Joints sharper than `crease_angle_deg` get flat normals.
Mesh make_revolution(const std::vector<vec2>& profile, float thickness, int segments,
                     float crease_angle_deg);

// The inner wall of a thick profile: `profile` offset by `thickness` to its left, reversed.
std::vector<vec2> thick_profile(const std::vector<vec2>& profile, float thickness);

// Applies a transform to positions, normals and tangents; a mirroring transform also reverses
// the winding so fronts stay on the same side of the surface.
void transform_mesh(Mesh& mesh, const glm::mat4& transform);

// Turns a mesh inside out: reversed winding, negated normals.
void flip_mesh(Mesh& mesh);

// Appends `src`'s vertices and triangles to `dst` (attributes present in both are kept).
void append_mesh(Mesh& dst, const Mesh& src);

// Replaces the normals with area-weighted vertex normals that stay smooth across edges whose
// faces differ by less than `crease_angle_deg` and are flat across sharper edges (vertices
// on a crease are split).
void compute_normals(Mesh& mesh, float crease_angle_deg);

// Per-vertex tangents (xyz, handedness in w) from the UVs, orthogonal to the normals, for
// bump and normal mapping. Without UVs, any unit vector orthogonal to the normal.
void compute_tangents(Mesh& mesh);

}  // namespace lb
