#include "blender_style_gltf.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <glm/gtc/constants.hpp>
#include <nlohmann/json.hpp>
#include <vector>

#include "bake/io/image_io.h"
#include "bake/io/uv_transform.h"
#include "bake/scene.h"
#include "bake/tangent_space.h"

namespace lb::test {

namespace {

using nlohmann::json;

// The binary buffer and its accessors, appended one array at a time.
struct BufferWriter {
  std::string bytes;
  json views = json::array(), accessors = json::array();

  int add(const void* data, size_t size, int component_type, size_t count, const char* type,
          json extra = json::object()) {
    while (bytes.size() % 4 != 0) bytes += '\0';
    views.push_back({{"buffer", 0}, {"byteOffset", bytes.size()}, {"byteLength", size}});
    bytes.append(static_cast<const char*>(data), size);
    json accessor = {{"bufferView", views.size() - 1},
                     {"componentType", component_type},
                     {"count", count},
                     {"type", type}};
    accessor.update(extra);
    accessors.push_back(accessor);
    return int(accessors.size() - 1);
  }
  template <typename V>
  int add_vectors(const std::vector<V>& values, const char* type, json extra = json::object()) {
    return add(values.data(), values.size() * sizeof(V), 5126, values.size(), type, extra);
  }
};

// DIR/NAME.gltf with the buffer's accessors and views, and DIR/NAME.bin; returns the .gltf.
std::string write_files(const std::string& dir, const std::string& name, json document,
                        const BufferWriter& buffer) {
  document["accessors"] = buffer.accessors;
  document["bufferViews"] = buffer.views;
  document["buffers"] = {{{"byteLength", buffer.bytes.size()}, {"uri", name + ".bin"}}};
  std::ofstream(dir + "/" + name + ".bin", std::ios::binary) << buffer.bytes;
  const std::string path = dir + "/" + name + ".gltf";
  std::ofstream(path, std::ios::binary) << document.dump(2);
  return path;
}

json texture_info(int index) {
  return {{"index", index},
          {"extensions",
           {{"KHR_texture_transform",
             {{"offset", {kFloorUvOffset[0], kFloorUvOffset[1]}},
              {"rotation", kFloorUvRotation},
              {"scale", {kFloorUvScale[0], kFloorUvScale[1]}}}}}}};
}

// A 1 x 1 m floor in its object's xz plane, facing +y, as an n x n grid; u along +x, v along
// +z (towards a viewer in front: down the image, as Blender writes a top view's UVs).
Mesh floor_grid(int n) {
  Mesh mesh;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const float u = float(i) / float(n), v = float(j) / float(n);
      mesh.positions.push_back({u - 0.5f, 0.0f, v - 0.5f});
      mesh.normals.push_back({0, 1, 0});
      mesh.uvs.push_back({u, v});
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const uint32_t a = uint32_t(j * (n + 1) + i), b = a + 1, c = a + uint32_t(n + 1), d = c + 1;
      // Counter-clockwise seen from +y.
      mesh.triangles.push_back({a, c, b});
      mesh.triangles.push_back({b, c, d});
    }
  return mesh;
}

void write_images(const std::string& dir) {
  // Base colour: 8 x 8 checker of 0.9 and 0.5 (sRGB bytes).
  std::vector<uint8_t> checker;
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x)
      for (int c = 0; c < 3; ++c) checker.push_back(((x + y) % 2) ? 230 : 128);
  write_png8(dir + "/floor_color.png", 8, 8, 3, checker);
  // Normal map: bumps with slopes up to 0.6 along both image axes (so a wrong handedness,
  // which flips the map's y, shows): n = (-0.6 cos 2 pi x, -0.6 sin 2 pi y, 1), normalised.
  std::vector<uint8_t> normals;
  const int size = 32;
  const float two_pi = 2.0f * glm::pi<float>();
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const glm::vec3 n = glm::normalize(
          glm::vec3(-0.6f * std::cos(two_pi * (float(x) + 0.5f) / float(size)),
                    -0.6f * std::sin(two_pi * (float(y) + 0.5f) / float(size)), 1.0f));
      for (int c = 0; c < 3; ++c)
        normals.push_back(uint8_t(std::lround((n[c] * 0.5f + 0.5f) * 255)));
    }
  write_png8(dir + "/floor_normal.png", size, size, 3, normals);
}

}  // namespace

std::string write_blender_style_gltf(const std::string& dir, const std::string& name,
                                     const BlenderStyleOptions& options) {
  write_images(dir);
  BufferWriter buffer;
  Mesh floor = floor_grid(4);
  json floor_attributes = {
      {"POSITION", buffer.add_vectors(floor.positions, "VEC3",
                                      {{"min", {-0.5, 0, -0.5}}, {"max", {0.5, 0, 0.5}}})},
      {"NORMAL", buffer.add_vectors(floor.normals, "VEC3")},
      {"TEXCOORD_0", buffer.add_vectors(floor.uvs, "VEC2")}};
  if (options.explicit_tangents) {
    Mesh transformed = floor;
    const glm::dmat3 m =
        uv_transform_matrix({kFloorUvOffset[0], kFloorUvOffset[1]}, kFloorUvRotation,
                            {kFloorUvScale[0], kFloorUvScale[1]});
    for (vec2& uv : transformed.uvs) uv = apply_uv_transform(m, uv);
    generate_mikktspace_tangents(transformed);
    if (options.negate_tangent_w)
      for (vec4& t : transformed.tangents) t.w = -t.w;
    floor_attributes["TANGENT"] = buffer.add_vectors(transformed.tangents, "VEC4");
  }
  std::vector<uint16_t> floor_indices;
  for (uvec3 t : floor.triangles)
    for (int k = 0; k < 3; ++k) floor_indices.push_back(uint16_t(t[k]));
  const int floor_index_accessor = buffer.add(floor_indices.data(), floor_indices.size() * 2, 5123,
                                              floor_indices.size(), "SCALAR");

  // Emissive panel: 0.4 x 0.4 m, facing -y.
  const std::vector<vec3> panel_positions = {
      {-0.2f, 0, -0.2f}, {0.2f, 0, -0.2f}, {0.2f, 0, 0.2f}, {-0.2f, 0, 0.2f}};
  const std::vector<vec3> panel_normals(4, vec3(0, -1, 0));
  const std::vector<uint16_t> panel_indices = {0, 1, 2, 0, 2, 3};
  json panel_attributes = {
      {"POSITION", buffer.add_vectors(panel_positions, "VEC3",
                                      {{"min", {-0.2, 0, -0.2}}, {"max", {0.2, 0, 0.2}}})},
      {"NORMAL", buffer.add_vectors(panel_normals, "VEC3")}};
  const int panel_index_accessor =
      buffer.add(panel_indices.data(), 12, 5123, panel_indices.size(), "SCALAR");

  // The animation Blender 4 writes for an animated emission colour: KHR_animation_pointer.
  const std::vector<float> times = {0.0f, 1.0f};
  const std::vector<vec3> colours = {{1, 1, 1}, {1, 0.5f, 0.25f}};
  const int time_accessor = buffer.add_vectors(times, "SCALAR", {{"min", {0.0}}, {"max", {1.0}}});
  const int colour_accessor = buffer.add_vectors(colours, "VEC3");

  const float s = float(std::sin(glm::radians(30.0) / 2)),
              c = float(std::cos(glm::radians(30.0) / 2));
  // Camera at (0, 2.2, 2.2) looking at the origin: rotated -45 degrees about x.
  const double q = std::sin(glm::radians(-45.0) / 2), w = std::cos(glm::radians(-45.0) / 2);
  json document = {
      {"asset", {{"version", "2.0"}, {"generator", "Khronos glTF Blender I/O v4.1.63 (style)"}}},
      {"extensionsUsed",
       {"KHR_lights_punctual", "KHR_texture_transform", "KHR_materials_emissive_strength",
        "KHR_animation_pointer"}},
      {"extensions",
       {{"KHR_lights_punctual",
         {{"lights",
           {{{"name", "Lamp"}, {"type", "point"}, {"color", {1, 1, 1}}, {"intensity", 54.35}},
            {{"name", "Spot"},
             {"type", "spot"},
             {"intensity", 100.0},
             {"spot", {{"innerConeAngle", 0.3}, {"outerConeAngle", 0.6}}}}}}}}}},
      {"scene", 0},
      {"scenes", {{{"name", "Scene"}, {"nodes", {0, 1, 2, 3, 4}}}}},
      {"nodes",
       {{{"name", "Floor"},
         {"mesh", 0},
         {"rotation", {0, s, 0, c}},  // 30 degrees about +y, uniform scale 2: a 2 x 2 m floor
         {"scale", {2, 2, 2}}},
        {{"name", "Panel"}, {"mesh", 1}, {"translation", {0.6, 1.2, 0.0}}},
        {{"name", "Lamp"},
         {"translation", {-0.5, 1.5, 0.5}},
         {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}},
        {{"name", "Spot"},
         {"translation", {0.5, 2.0, -0.5}},
         {"rotation", {-0.7071068, 0, 0, 0.7071068}},
         {"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}},
        {{"name", "Camera"},
         {"camera", 0},
         {"translation", {0, 2.2, 2.2}},
         {"rotation", {q, 0, 0, w}}}}},
      {"cameras",
       {{{"type", "perspective"},
         {"perspective",
          {{"yfov", 0.8}, {"znear", 0.1}, {"zfar", 100}, {"aspectRatio", 4.0 / 3}}}}}},
      {"meshes",
       {{{"name", "Floor"},
         {"primitives",
          {{{"attributes", floor_attributes},
            {"indices", floor_index_accessor},
            {"material", 0}}}}},
        {{"name", "Panel"},
         {"primitives",
          {{{"attributes", panel_attributes},
            {"indices", panel_index_accessor},
            {"material", 1}}}}}}},
      {"materials",
       {{{"name", "Floor"},
         {"pbrMetallicRoughness",
          {{"baseColorTexture", texture_info(0)}, {"metallicFactor", 0}, {"roughnessFactor", 0.5}}},
         {"normalTexture", texture_info(1)}},
        {{"name", "Emission"},
         {"emissiveFactor", {1, 1, 1}},
         {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 20}}}}},
         {"pbrMetallicRoughness", {{"baseColorFactor", {0, 0, 0, 1}}, {"metallicFactor", 0}}}}}},
      {"textures", {{{"sampler", 0}, {"source", 0}}, {{"sampler", 0}, {"source", 1}}}},
      {"samplers", {{{"magFilter", 9729}, {"minFilter", 9987}}}},
      {"images",
       {{{"name", "floor_color"}, {"mimeType", "image/png"}, {"uri", "floor_color.png"}},
        {{"name", "floor_normal"}, {"mimeType", "image/png"}, {"uri", "floor_normal.png"}}}},
      {"animations",
       {{{"name", "EmissionAction"},
         {"channels",
          {{{"sampler", 0},
            {"target",
             {{"path", "pointer"},
              {"extensions",
               {{"KHR_animation_pointer", {{"pointer", "/materials/1/emissiveFactor"}}}}}}}}}},
         {"samplers",
          {{{"input", time_accessor},
            {"output", colour_accessor},
            {"interpolation", "LINEAR"}}}}}}},
  };
  if (options.double_sided_panel) document["materials"][1]["doubleSided"] = true;
  return write_files(dir, name, document, buffer);
}

std::string write_textured_quad_gltf(const std::string& dir, const std::string& name,
                                     const std::vector<glm::vec2>& uv0,
                                     const std::vector<glm::vec2>& uv1,
                                     const std::string& texture_extensions) {
  write_images(dir);
  BufferWriter buffer;
  const std::vector<vec3> positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  const std::vector<vec3> normals(4, vec3(0, 0, 1));
  const std::vector<uint16_t> indices = {0, 1, 2, 0, 2, 3};
  json attributes = {
      {"POSITION", buffer.add_vectors(positions, "VEC3", {{"min", {0, 0, 0}}, {"max", {1, 1, 0}}})},
      {"NORMAL", buffer.add_vectors(normals, "VEC3")},
      {"TEXCOORD_0", buffer.add_vectors(uv0, "VEC2")}};
  if (!uv1.empty()) attributes["TEXCOORD_1"] = buffer.add_vectors(uv1, "VEC2");
  const int index_accessor = buffer.add(indices.data(), 12, 5123, 6, "SCALAR");
  json texture = {{"index", 0}};
  const json extensions = json::parse(texture_extensions);
  if (!extensions.empty()) texture["extensions"] = extensions;
  const json document = {
      {"asset", {{"version", "2.0"}}},
      {"scene", 0},
      {"scenes", {{{"nodes", {0}}}}},
      {"nodes", {{{"mesh", 0}}}},
      {"meshes",
       {{{"primitives",
          {{{"attributes", attributes}, {"indices", index_accessor}, {"material", 0}}}}}}},
      {"materials",
       {{{"pbrMetallicRoughness", {{"baseColorTexture", texture}, {"metallicFactor", 0}}}}}},
      {"textures", {{{"source", 0}}}},
      {"images", {{{"uri", "floor_color.png"}}}},
  };
  return write_files(dir, name, document, buffer);
}

}  // namespace lb::test
