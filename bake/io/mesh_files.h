#pragma once
// Triangle meshes from files OpenMesh reads: OBJ, PLY, OFF, STL, OM (ASCII or binary).

#include <string>
#include <vector>

#include "bake/scene.h"

namespace lb {

// Reads the mesh at `path` in its own frame: polygons triangulated, UVs when the file has
// them, the file's normals or, when it has none, normals flat across edges sharper than
// `crease_angle_deg`. Problems throw SceneError starting with `where` and naming the file;
// OBJ index and coordinate errors name the line. Faces the reader had to drop (repeated
// vertices) are counted in a warning.
Mesh read_mesh_file(const std::string& path, float crease_angle_deg, const std::string& where,
                    std::vector<std::string>& warnings);

}  // namespace lb
