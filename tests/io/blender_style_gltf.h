#pragma once
// Writes a glTF laid out as Blender 4's exporter writes a lamp-lit room: KHR_lights_punctual
// lamps, an emissive panel, a floor whose base colour and normal textures carry the same
// KHR_texture_transform, a KHR_animation_pointer animation, no TANGENT (unless asked).
// Images and the .bin are written beside the .gltf; nothing is downloaded.

#include <glm/glm.hpp>
#include <string>
#include <vector>

namespace lb::test {

struct BlenderStyleOptions {
  // Write TANGENT: MikkTSpace tangents of the floor computed with the transformed UVs (what
  // the loader generates), in the mesh's object space.
  bool explicit_tangents = false;
  bool negate_tangent_w = false;  // with explicit_tangents: a wrong handedness, for contrast
  bool double_sided_panel = false;  // the emissive panel's material `doubleSided: true`
};

// The floor's texture transform (KHR_texture_transform on both of its textures).
constexpr double kFloorUvOffset[2] = {0.1, 0.2};
constexpr double kFloorUvRotation = 0.4;  // radians
constexpr double kFloorUvScale[2] = {2.0, 2.0};

// Writes DIR/NAME (.gltf) with its buffer and images; returns the .gltf's path.
std::string write_blender_style_gltf(const std::string& dir, const std::string& name,
                                     const BlenderStyleOptions& options);

// A 1 x 1 m quad in the xy plane, facing +z, vertices (0,0), (1,0), (1,1), (0,1), with
// TEXCOORD_0 = uv0 and, if given, TEXCOORD_1 = uv1, textured with floor_color.png through a
// baseColorTexture whose extensions are `texture_extensions` (a JSON object, "{}" for none).
// Returns the .gltf's path.
std::string write_textured_quad_gltf(const std::string& dir, const std::string& name,
                                     const std::vector<glm::vec2>& uv0,
                                     const std::vector<glm::vec2>& uv1,
                                     const std::string& texture_extensions);

}  // namespace lb::test
