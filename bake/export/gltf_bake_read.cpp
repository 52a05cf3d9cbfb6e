#include "bake/export/gltf_bake_read.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cstring>
#include <numbers>
#include <filesystem>
#include <stdexcept>

#include "bake/fnv1a.h"
#include "bake/io/gltf_directional.h"
#include "bake/export/gltf_export.h"
#include "bake/export/gltf_light_groups.h"
#include "bake/io/image_io.h"
#include "bake/io/ktx2_encode.h"
#include "bake/light_groups.h"

namespace lb {

namespace {

namespace fs = std::filesystem;

// The primitives in the loader's order: the default scene's nodes depth first, children in
// order, one scene mesh per triangle primitive (docs/gltf.md).
void collect(const tinygltf::Model& model, int node_index,
             std::vector<const tinygltf::Primitive*>& out, int depth) {
  if (node_index < 0 || size_t(node_index) >= model.nodes.size() || depth > 64) return;
  const tinygltf::Node& node = model.nodes[size_t(node_index)];
  // A moving object (extras.dynamic) is no scene mesh: it has no baked light.
  const bool dynamic = node.extras.IsObject() && node.extras.Has("dynamic") &&
                       node.extras.Get("dynamic").IsBool() && node.extras.Get("dynamic").Get<bool>();
  if (!dynamic && node.mesh >= 0 && size_t(node.mesh) < model.meshes.size())
    for (const tinygltf::Primitive& p : model.meshes[size_t(node.mesh)].primitives)
      if (p.mode == TINYGLTF_MODE_TRIANGLES || p.mode == -1) out.push_back(&p);
  for (int child : node.children) collect(model, child, out, depth + 1);
}

std::vector<vec3> read_vec3(const tinygltf::Model& model, int accessor_index,
                            const std::string& path) {
  const tinygltf::Accessor& a = model.accessors.at(size_t(accessor_index));
  if (a.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT || a.type != TINYGLTF_TYPE_VEC3 ||
      a.bufferView < 0 || a.sparse.isSparse)
    throw std::runtime_error(path + ": COLOR_0 is not the float VEC3 lightbake writes");
  const tinygltf::BufferView& view = model.bufferViews.at(size_t(a.bufferView));
  const std::vector<unsigned char>& data = model.buffers.at(size_t(view.buffer)).data;
  const size_t stride = view.byteStride ? view.byteStride : sizeof(vec3);
  const size_t offset = view.byteOffset + a.byteOffset;
  if (a.count > 0 && offset + (a.count - 1) * stride + sizeof(vec3) > data.size())
    throw std::runtime_error(path + ": COLOR_0 runs past its buffer");
  std::vector<vec3> out(a.count);
  for (size_t i = 0; i < a.count; ++i)
    std::memcpy(&out[i], &data[offset + i * stride], sizeof(vec3));
  return out;
}

// The map: the EXR beside the file when it is there and the right size, else the PNG.
void read_map(const tinygltf::Model& model, const tinygltf::Material& material,
              const std::string& path, IlluminationMaps& maps) {
  const tinygltf::Value& moz = material.extensions.at("MOZ_lightmap");
  const int texture = moz.Get("index").GetNumberAsInt();
  if (texture < 0 || size_t(texture) >= model.textures.size())
    throw std::runtime_error(path + ": MOZ_lightmap names no texture");
  const int source = model.textures[size_t(texture)].source;
  if (source < 0 || size_t(source) >= model.images.size())
    throw std::runtime_error(path + ": the lightmap texture has no image");
  const tinygltf::Image& image = model.images[size_t(source)];
  const tinygltf::Value& extras = material.extras.Get("lightbake_lightmap");
  maps.width = image.width;
  maps.height = image.height;
  maps.radiance.assign(size_t(image.width) * size_t(image.height), vec3(0.0f));
  maps.holds_direct_light =
      extras.Get("includes_direct").IsBool() && extras.Get("includes_direct").Get<bool>();
  // The half-float EXR first, then the Radiance HDR, then the PNG inside the file.
  for (const char* key : {"hdr", "radiance_hdr"}) {
    if (!extras.Get(key).IsString()) continue;
    const fs::path file = fs::path(path).parent_path() / extras.Get(key).Get<std::string>();
    if (!fs::exists(file)) continue;
    // The export records each map's hash (older exports did not): a map that is not the one
    // this file was written with (another export's, to the same name) is refused.
    const tinygltf::Value& recorded = extras.Get(std::string(key) + "_fnv1a");
    if (recorded.IsString()) {
      const std::string hash = file_fnv1a_hex(file.string());
      if (hash != recorded.Get<std::string>())
        throw std::runtime_error(file.string() + ": its FNV-1a " + hash + " is not the " +
                                 recorded.Get<std::string>() + " that " + path +
                                 " records: it belongs to another export; export again");
    }
    const Image hdr = read_image(file.string());
    if (hdr.width == image.width && hdr.height == image.height && hdr.channels >= 3) {
      for (size_t i = 0; i < maps.radiance.size(); ++i)
        for (int c = 0; c < 3; ++c)
          maps.radiance[i][c] = hdr.pixels[i * size_t(hdr.channels) + size_t(c)];
      return;
    }
  }
  const double scale = extras.Get("scale").IsNumber()
                           ? extras.Get("scale").GetNumberAsDouble()
                           : moz.Get("intensity").GetNumberAsDouble() / 3.14159265358979323846;
  const bool rgbm = extras.Get("encoding").IsString() &&
                    extras.Get("encoding").Get<std::string>() == "rgbm8";
  if (image.bits != 8 || image.component < (rgbm ? 4 : 3) ||
      image.image.size() < maps.radiance.size() * size_t(image.component))
    throw std::runtime_error(path + ": the lightmap image is not the 8-bit " +
                             (rgbm ? "RGBA" : "RGB") + " lightbake writes");
  const LightmapEncoding encoding = rgbm ? LightmapEncoding::rgbm : LightmapEncoding::srgb;
  for (size_t i = 0; i < maps.radiance.size(); ++i)
    maps.radiance[i] = decode_lightmap_texel(&image.image[i * size_t(image.component)], encoding,
                                             float(scale));
}

// The light groups' layers (LIGHTBAKE_lightmap_groups, gltf_light_groups.h), each decoded as the
// MOZ_lightmap PNG is, with its own intensity, into group_radiance in the order of the scene's
// groups (light_group_names), so that blend_light_groups weighs them (`--group-weights` on an
// export); nothing when the material has none.
void read_group_layers(const tinygltf::Model& model, const tinygltf::Material& material,
                       const std::string& path, const Scene& scene, BakeResult& bake) {
  const auto found = material.extensions.find(kLightGroupsExtension);
  if (found == material.extensions.end()) return;
  // COLOR_0 (vertex radiosity, older exports) holds the default mix alone: no groups then.
  for (const MeshRadiosity& m : bake.radiosity.meshes)
    if (!m.vertex_radiance.empty()) return;
  const std::string where = path + ": " + kLightGroupsExtension;
  const tinygltf::Value& layers = found->second.Get("layers");
  const std::vector<std::string> groups = light_group_names(scene);
  if (!layers.IsArray() || layers.ArrayLen() != groups.size())
    throw std::runtime_error(where + " has not one layer for each of the scene's " +
                             std::to_string(groups.size()) + " light groups");
  const tinygltf::Value& extras = material.extras.Get("lightbake_lightmap");
  const bool rgbm = extras.Get("encoding").IsString() &&
                    extras.Get("encoding").Get<std::string>() == "rgbm8";
  IlluminationMaps& maps = bake.illumination;
  maps.group_radiance.assign(groups.size(), {});
  for (size_t k = 0; k < layers.ArrayLen(); ++k) {
    const tinygltf::Value& layer = layers.Get(int(k));
    const std::string name =
        layer.Get("name").IsString() ? layer.Get("name").Get<std::string>() : std::string();
    const auto g = std::find(groups.begin(), groups.end(), name);
    const int texture = layer.Get("index").IsNumber() ? layer.Get("index").GetNumberAsInt() : -1;
    const int source = texture >= 0 && size_t(texture) < model.textures.size()
                           ? model.textures[size_t(texture)].source
                           : -1;
    if (g == groups.end() || !maps.group_radiance[size_t(g - groups.begin())].empty() ||
        source < 0 || size_t(source) >= model.images.size() || !layer.Get("intensity").IsNumber())
      throw std::runtime_error(where + ": layer " + std::to_string(k) + " ('" + name +
                               "') is not one of the scene's groups with an image and intensity");
    const tinygltf::Image& image = model.images[size_t(source)];
    if (image.width != maps.width || image.height != maps.height || image.bits != 8 ||
        image.component < (rgbm ? 4 : 3) ||
        image.image.size() < maps.radiance.size() * size_t(image.component))
      throw std::runtime_error(where + ": layer '" + name + "' is not an 8-bit map of the " +
                               "lightmap's size");
    const float scale = float(layer.Get("intensity").GetNumberAsDouble() / std::numbers::pi);
    std::vector<vec3>& radiance = maps.group_radiance[size_t(g - groups.begin())];
    radiance.resize(maps.radiance.size());
    for (size_t i = 0; i < radiance.size(); ++i)
      radiance[i] = decode_lightmap_texel(&image.image[i * size_t(image.component)],
                                          rgbm ? LightmapEncoding::rgbm : LightmapEncoding::srgb,
                                          scale);
  }
  bake.light_groups = groups;
  bake.radiosity.group_vertex_radiance.assign(
      groups.size(), std::vector<std::vector<vec3>>(bake.radiosity.meshes.size()));
}

// The L1 band (LIGHTBAKE_lightmap_directional, gltf_directional.h), decoded against the L0
// just read; nothing when the material has none.
void read_directional(const tinygltf::Model& model, const tinygltf::Material& material,
                      const std::string& path, IlluminationMaps& maps) {
  const auto found = material.extensions.find(kDirectionalExtension);
  if (found == material.extensions.end()) return;
  const tinygltf::Value& l1 = found->second.Get("l1");
  if (!l1.IsArray() || l1.ArrayLen() != 3)
    throw std::runtime_error(path + ": " + kDirectionalExtension + ".l1 is not 3 textures");
  // "share": s in the x map's alpha or none; a file without the key (before it) has s in that
  // alpha when the map has one.
  const tinygltf::Value& share_key = found->second.Get("share");
  if (share_key.Type() != tinygltf::NULL_TYPE && !share_key.IsBool())
    throw std::runtime_error(path + ": " + kDirectionalExtension + ".share is not true or false");
  for (size_t a = 0; a < 3; ++a) {
    const int texture = l1.Get(int(a)).Get("index").GetNumberAsInt();
    const int source = texture >= 0 && size_t(texture) < model.textures.size()
                           ? model.textures[size_t(texture)].source
                           : -1;
    if (source < 0 || size_t(source) >= model.images.size())
      throw std::runtime_error(path + ": " + kDirectionalExtension + ".l1[" +
                               std::to_string(a) + "] names no image");
    const tinygltf::Image& image = model.images[size_t(source)];
    if (image.width != maps.width || image.height != maps.height || image.bits != 8 ||
        image.component < 3 ||
        image.image.size() < maps.radiance.size() * size_t(image.component))
      throw std::runtime_error(path + ": " + kDirectionalExtension + ".l1[" +
                               std::to_string(a) + "] is not an 8-bit RGB map of the " +
                               "lightmap's size");
    maps.l1[a].resize(maps.radiance.size());
    for (size_t i = 0; i < maps.radiance.size(); ++i)
      maps.l1[a][i] =
          decode_l1_ratio(&image.image[i * size_t(image.component)], maps.radiance[i]);
    if (a == 0) {  // s in the x map's alpha; 0 without it
      const bool share = share_key.IsBool() ? share_key.Get<bool>() : image.component == 4;
      if (share && image.component != 4)
        throw std::runtime_error(path + ": " + kDirectionalExtension +
                                 ".l1[0] has no alpha but \"share\" is true");
      maps.l1_share.assign(maps.radiance.size(), 0.0f);
      if (share)
        for (size_t i = 0; i < maps.radiance.size(); ++i)
          maps.l1_share[i] = float(image.image[i * 4 + 3]) / 255.0f;
    }
  }
}

}  // namespace

BakeResult read_gltf_bake(const std::string& path, const Scene& scene) {
  if (!is_lightbake_gltf(path))
    throw std::runtime_error(path + ": not a glTF written by `lightbake export`; bake it instead");
  tinygltf::TinyGLTF loader;
  // A KTX2 copy of the map (export --ktx2) stays undecoded: the texture's PNG source is read.
  loader.SetImageLoader(
      [](tinygltf::Image* image, const int index, std::string* err, std::string* warn, int w,
         int h, const unsigned char* bytes, int size, void* user) {
        return is_ktx2_data(bytes, size_t(std::max(size, 0))) ||
               tinygltf::LoadImageData(image, index, err, warn, w, h, bytes, size, user);
      },
      nullptr);
  tinygltf::Model model;
  std::string err, warn;
  const bool binary = fs::path(path).extension() == ".glb";
  if (!(binary ? loader.LoadBinaryFromFile(&model, &err, &warn, path)
               : loader.LoadASCIIFromFile(&model, &err, &warn, path)))
    throw std::runtime_error(path + ": " + err);

  std::vector<const tinygltf::Primitive*> primitives;
  const int default_scene = model.defaultScene >= 0 ? model.defaultScene : 0;
  if (size_t(default_scene) < model.scenes.size())
    for (int node : model.scenes[size_t(default_scene)].nodes) collect(model, node, primitives, 0);
  if (primitives.size() != scene.meshes.size())
    throw std::runtime_error(path + ": " + std::to_string(primitives.size()) +
                             " primitives but the loaded scene has " +
                             std::to_string(scene.meshes.size()) + " meshes");

  const tinygltf::Value& scale_value = model.asset.extras.Get("lightbake_color_0_scale");
  const float color_scale = scale_value.IsNumber() ? float(scale_value.GetNumberAsDouble()) : 1.0f;
  BakeResult bake;
  const size_t n = scene.meshes.size();
  bake.radiosity.meshes.resize(n);
  bake.illumination.lightmap_uvs.resize(n);
  bake.illumination.vertex_splits.resize(n);
  uint32_t next_patch = 0;
  bool map_read = false;
  const tinygltf::Material* layered = nullptr;  // the material whose map was read
  for (size_t m = 0; m < n; ++m) {
    const tinygltf::Primitive& p = *primitives[m];
    const Mesh& mesh = scene.meshes[m];
    if (auto colour = p.attributes.find("COLOR_0"); colour != p.attributes.end()) {
      std::vector<vec3> radiance = read_vec3(model, colour->second, path);
      if (radiance.size() != mesh.positions.size())
        throw std::runtime_error(path + ": COLOR_0 of mesh '" + mesh.name +
                                 "' does not match its vertices");
      for (vec3& r : radiance) r *= color_scale;
      MeshRadiosity& out = bake.radiosity.meshes[m];
      out.mesh = mesh;
      out.vertex_radiance = std::move(radiance);
      out.triangle_patch.resize(mesh.triangles.size());
      for (uint32_t& patch : out.triangle_patch) patch = next_patch++;
    }
    if (p.material < 0 || size_t(p.material) >= model.materials.size()) continue;
    const tinygltf::Material& material = model.materials[size_t(p.material)];
    if (!material.extensions.count("MOZ_lightmap") ||
        mesh.lightmap_uvs.size() != mesh.positions.size())
      continue;
    if (!map_read) {
      read_map(model, material, path, bake.illumination);
      read_directional(model, material, path, bake.illumination);
      layered = &material;
    }
    map_read = true;
    bake.illumination.lightmap_uvs[m] = mesh.lightmap_uvs;
  }
  if (layered) read_group_layers(model, *layered, path, scene, bake);
  bake.radiosity.stats.patch_count = next_patch;
  const tinygltf::Value& seed = model.asset.extras.Get("lightbake_seed");
  if (seed.IsNumber()) bake.seed = uint64_t(seed.GetNumberAsDouble());
  return bake;
}

}  // namespace lb
