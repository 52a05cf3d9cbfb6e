#include "bake/export/gltf_export.h"
#include "bake/io/ktx2_encode.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <glm/gtc/constants.hpp>
#include <glm/gtc/quaternion.hpp>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <type_traits>

#include "bake/export/gltf_light_groups.h"
#include "bake/export/rgbm_blocks.h"
#include "bake/fnv1a.h"
#include "bake/io/atomic_file.h"
#include "bake/io/gltf_directional.h"
#include "bake/io/height_to_normal.h"
#include "bake/io/image_codecs.h"
#include "bake/json_text.h"
#include "bake/light_groups.h"
#include "bake/surface.h"

namespace lb {

namespace {

namespace fs = std::filesystem;
using tinygltf::Value;

constexpr char kGenerator[] = "lightbake";
constexpr char kUnits[] = "W/(sr m^2)";
constexpr char kConvention[] =
    "E/pi: incident irradiance E (W/m^2) divided by pi, linear Rec.709 RGB, before the "
    "surface's reflectance; rendered radiance = albedo * (direct + lightmap) with contents "
    "'indirect', albedo * lightmap with contents 'all'";

const char* contents_text(LightmapContents contents) {
  return contents == LightmapContents::all
             ? "all: direct light from the area lights + caustics (light after one or more "
               "specular bounces) + soft light (two or more diffuse bounces); the engine adds "
               "no light of its own"
             : "indirect: caustics (light after one or more specular bounces) + soft light (two "
               "or more diffuse bounces); the engine adds the direct light";
}

// ---- PNG encoding ---------------------------------------------------------------------------

// Through OpenImageIO, as every image the tool writes (image_codecs.h).
std::vector<unsigned char> encode_png(int width, int height, int channels,
                                      const std::vector<uint8_t>& bytes) {
  codecs::Pixels pixels;
  pixels.width = width;
  pixels.height = height;
  pixels.channels = channels;
  pixels.bytes = bytes.data();
  pixels.stored = SampleType::uint8;
  try {
    return codecs::encode("png", pixels);
  } catch (const std::exception& e) {
    throw std::runtime_error("PNG encoding failed (" + std::to_string(width) + "x" +
                             std::to_string(height) + "): " + e.what());
  }
}

// A scene texture back to 8 bits: colour channels re-encoded to sRGB when the loader decoded
// them (an 8-bit sRGB source comes back byte for byte), alpha and data maps as stored.
std::vector<unsigned char> texture_png(const Texture& texture) {
  const int channels = std::clamp(texture.channels, 1, 4);
  const int colour_channels = channels == 2 || channels == 4 ? channels - 1 : channels;
  std::vector<uint8_t> bytes(texture.texels.size());
  for (size_t i = 0; i < texture.texels.size(); ++i) {
    const bool colour = int(i % size_t(channels)) < colour_channels;
    const float v = texture.texels[i];
    const bool encode = colour && texture.srgb_decoded;
    bytes[i] = unit_to_byte(encode ? srgb_oetf(std::clamp(v, 0.0f, 1.0f)) : v);
  }
  return encode_png(texture.width, texture.height, channels, bytes);
}

// glTF carries a masked or blended material's alpha in its base colour texture's fourth
// channel; the loader keeps them apart (Material::alpha_texture). So: the colour texture (or
// white, where the colour is the factor alone) with the alpha resampled at its texels.
Texture base_colour_with_alpha(const Texture* colour, const Texture& alpha) {
  Texture out;
  out.path = (colour ? colour->path : alpha.path) + " with alpha";
  out.width = colour ? colour->width : alpha.width;
  out.height = colour ? colour->height : alpha.height;
  out.channels = 4;
  out.srgb_decoded = colour ? colour->srgb_decoded : true;
  const Texture& sampled = colour ? *colour : alpha;  // one texture, one sampler
  out.filter = sampled.filter, out.wrap_u = sampled.wrap_u, out.wrap_v = sampled.wrap_v;
  const bool same_grid = out.width == alpha.width && out.height == alpha.height;
  out.texels.reserve(size_t(out.width) * size_t(out.height) * 4);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) {
      const size_t i = size_t(y) * size_t(out.width) + size_t(x);
      const vec2 uv((float(x) + 0.5f) / float(out.width), (float(y) + 0.5f) / float(out.height));
      const vec4 rgb = colour ? sample_texture(*colour, uv) : vec4(1.0f);
      const float a = same_grid ? alpha.texels[i * size_t(std::max(alpha.channels, 1))]
                                : sample_texture(alpha, uv).x;
      out.texels.insert(out.texels.end(), {rgb.x, rgb.y, rgb.z, a});
    }
  return out;
}

// ---- buffer and accessors ------------------------------------------------------------------

struct Writer {
  tinygltf::Model model;

  int add_view(const void* data, size_t size, int target) {
    std::vector<unsigned char>& buffer = model.buffers[0].data;
    const size_t offset = buffer.size();
    const auto* bytes = static_cast<const unsigned char*>(data);
    buffer.insert(buffer.end(), bytes, bytes + size);
    buffer.resize((buffer.size() + 3) / 4 * 4, 0);  // every view starts 4-byte aligned
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = offset;
    view.byteLength = size;
    view.target = target;
    model.bufferViews.push_back(view);
    return int(model.bufferViews.size() - 1);
  }

  // Float attribute of `components` floats per element.
  int add_floats(const float* data, size_t count, int components, bool min_max = false) {
    tinygltf::Accessor accessor;
    accessor.bufferView =
        add_view(data, count * size_t(components) * sizeof(float), TINYGLTF_TARGET_ARRAY_BUFFER);
    accessor.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
    accessor.count = count;
    accessor.type = components == 2   ? TINYGLTF_TYPE_VEC2
                    : components == 3 ? TINYGLTF_TYPE_VEC3
                                      : TINYGLTF_TYPE_VEC4;
    if (min_max && count > 0) {
      accessor.minValues.assign(size_t(components), 1e300);
      accessor.maxValues.assign(size_t(components), -1e300);
      for (size_t i = 0; i < count; ++i)
        for (int c = 0; c < components; ++c) {
          const double v = data[i * size_t(components) + size_t(c)];
          accessor.minValues[size_t(c)] = std::min(accessor.minValues[size_t(c)], v);
          accessor.maxValues[size_t(c)] = std::max(accessor.maxValues[size_t(c)], v);
        }
    }
    model.accessors.push_back(accessor);
    return int(model.accessors.size() - 1);
  }

  int add_indices(const std::vector<uvec3>& triangles) {
    tinygltf::Accessor accessor;
    accessor.bufferView = add_view(triangles.data(), triangles.size() * sizeof(uvec3),
                                   TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    accessor.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
    accessor.count = triangles.size() * 3;
    accessor.type = TINYGLTF_TYPE_SCALAR;
    model.accessors.push_back(accessor);
    return int(model.accessors.size() - 1);
  }

  int add_png_image(const std::string& name, const std::vector<unsigned char>& png) {
    return add_image(name, png, "image/png");
  }
  int add_image(const std::string& name, const std::vector<unsigned char>& bytes,
                const std::string& mime_type) {
    tinygltf::Image image;
    image.name = valid_utf8(name);
    image.mimeType = mime_type;
    image.bufferView = add_view(bytes.data(), bytes.size(), 0);
    model.images.push_back(image);
    return int(model.images.size() - 1);
  }

  int add_texture(int image, int sampler) {
    tinygltf::Texture texture;
    texture.source = image;
    texture.sampler = sampler;
    model.textures.push_back(texture);
    return int(model.textures.size() - 1);
  }

  int add_sampler(int wrap, bool nearest = false, int wrap_t = -1) {
    tinygltf::Sampler sampler;
    sampler.magFilter = nearest ? TINYGLTF_TEXTURE_FILTER_NEAREST : TINYGLTF_TEXTURE_FILTER_LINEAR;
    sampler.minFilter = nearest ? TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_LINEAR
                                : TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR;
    sampler.wrapS = wrap;
    sampler.wrapT = wrap_t >= 0 ? wrap_t : wrap;
    model.samplers.push_back(sampler);
    return int(model.samplers.size() - 1);
  }

  void use_extension(const std::string& name) {
    if (std::find(model.extensionsUsed.begin(), model.extensionsUsed.end(), name) ==
        model.extensionsUsed.end())
      model.extensionsUsed.push_back(name);
  }
};

std::vector<vec3> unit_normals(const std::vector<vec3>& normals) {
  std::vector<vec3> out(normals.size());
  for (size_t i = 0; i < normals.size(); ++i) {
    const float length = glm::length(normals[i]);
    out[i] = length > 0.0f ? normals[i] / length : vec3(0.0f, 0.0f, 1.0f);
  }
  return out;
}

std::vector<vec4> unit_tangents(const std::vector<vec4>& tangents) {
  std::vector<vec4> out(tangents.size());
  for (size_t i = 0; i < tangents.size(); ++i) {
    const vec3 t(tangents[i]);
    const float length = glm::length(t);
    out[i] = vec4(length > 0.0f ? t / length : vec3(1.0f, 0.0f, 0.0f),
                  tangents[i].w < 0.0f ? -1.0f : 1.0f);
  }
  return out;
}

Value number(double v) {
  return Value(v);
}

// The 27 numbers of one probe's coefficients, coefficient by coefficient, RGB each.
Value sh_value(const ShL2& sh) {
  Value::Array numbers;
  for (const vec3& c : sh)
    for (int k = 0; k < 3; ++k) numbers.push_back(number(c[k]));
  return Value(numbers);
}

// scene.extensions.LIGHTBAKE_light_probes (docs/light-probes.md, "In the exported file").
Value probe_grid_value(const ProbeGrid& grid) {
  auto triple = [](vec3 v) {
    return Value(Value::Array{number(v.x), number(v.y), number(v.z)});
  };
  Value::Object out;
  out["origin"] = triple(grid.origin);
  out["spacing"] = triple(grid.spacing);
  out["counts"] = Value(Value::Array{Value(grid.counts.x), Value(grid.counts.y),
                                     Value(grid.counts.z)});
  Value::Array valid, coefficients;
  for (size_t p = 0; p < grid.size(); ++p) {
    valid.push_back(Value(int(grid.valid[p])));
    for (const vec3& c : grid.sh[p])
      for (int k = 0; k < 3; ++k) coefficients.push_back(number(c[k]));
  }
  out["valid"] = Value(valid);
  out["coefficients"] = Value(coefficients);
  out["convention"] = Value(std::string(
      "L2 SH of incident radiance, W/(sr m^2) per linear RGB channel, three.js "
      "SphericalHarmonics3 order and normalisation, world axes; probe i + nx (j + ny k), 27 "
      "numbers each"));
  return Value(out);
}

Value lightmap_extras(const LightmapPng& map, const GltfExportOptions& options,
                      float texel_density_per_m) {
  Value::Object o;
  o["units"] = Value(std::string(kUnits));
  o["convention"] = Value(std::string(kConvention));
  const bool rgbm = map.encoding == LightmapEncoding::rgbm;
  o["encoding"] = Value(std::string(rgbm ? "rgbm8" : "srgb8-scaled"));
  o["decode"] = Value(std::string(rgbm ? "linear = (rgb / 255) * (alpha / 255) * scale"
                                       : "linear = srgb_eotf(byte / 255) * scale"));
  if (rgbm && !options.ktx2_encoder.empty())  // rgbm_blocks.h: what UASTC keeps
    o["ktx2_layout"] = Value(std::string(
        "rgbm8 with one alpha per 4x4 block and its own mip chain in linear light; same decode"));
  o["scale"] = number(map.scale);
  o["intensity"] = number(glm::pi<double>() * map.scale);
  o["contents"] = Value(std::string(to_string(options.contents)));
  o["contents_description"] = Value(std::string(contents_text(options.contents)));
  o["includes_direct"] = Value(options.contents == LightmapContents::all);
  o["texel_density_per_m"] = number(texel_density_per_m);
  if (options.denoise_direct && options.contents == LightmapContents::all)
    o["denoised"] = Value(std::string("direct term: Open Image Denoise, RT filter"));
  if (!options.exr_name.empty()) o["hdr"] = Value(valid_utf8(options.exr_name));
  if (!options.exr_fnv1a.empty()) o["hdr_fnv1a"] = Value(options.exr_fnv1a);
  if (!options.hdr_name.empty()) o["radiance_hdr"] = Value(valid_utf8(options.hdr_name));
  if (!options.hdr_fnv1a.empty()) o["radiance_hdr_fnv1a"] = Value(options.hdr_fnv1a);
  return Value(o);
}

// The metallic-roughness material the glTF loader maps back to `material` (docs/gltf.md).
// `height_normal`: the glTF texture of the material's height bump as a normal map
// (height_to_normal.h), -1 if none.
tinygltf::Material make_material(const Material& material, Writer& writer,
                                 const std::vector<int>& texture_of, int height_normal,
                                 int base_colour_with_alpha) {
  tinygltf::Material out;
  out.name = valid_utf8(material.name);
  auto& pbr = out.pbrMetallicRoughness;
  const vec3 r = material.reflectance;
  pbr.baseColorFactor = {r.x, r.y, r.z, 1.0};
  switch (material.kind) {
    case MaterialKind::diffuse:
      pbr.metallicFactor = 0.0;
      pbr.roughnessFactor = 1.0;
      if (material.reflectance_texture >= 0 &&
          size_t(material.reflectance_texture) < texture_of.size())
        pbr.baseColorTexture.index = texture_of[size_t(material.reflectance_texture)];
      if (base_colour_with_alpha >= 0) pbr.baseColorTexture.index = base_colour_with_alpha;
      if (material.bump == BumpKind::normal_map && material.bump_texture >= 0 &&
          size_t(material.bump_texture) < texture_of.size()) {
        out.normalTexture.index = texture_of[size_t(material.bump_texture)];
        out.normalTexture.scale = material.bump_scale;
      }
      if (material.bump == BumpKind::height && height_normal >= 0)
        out.normalTexture.index = height_normal;
      break;
    case MaterialKind::mirror:
      pbr.metallicFactor = 1.0;
      pbr.roughnessFactor = 0.0;
      break;
    case MaterialKind::glossy:
      pbr.metallicFactor = 1.0;
      pbr.roughnessFactor = material.roughness;
      break;
    case MaterialKind::glass: {
      pbr.metallicFactor = 0.0;
      pbr.roughnessFactor = 0.0;
      Value::Object transmission;
      transmission["transmissionFactor"] = number(1.0);
      out.extensions["KHR_materials_transmission"] = Value(transmission);
      Value::Object ior;
      ior["ior"] = number(material.ior);
      out.extensions["KHR_materials_ior"] = Value(ior);
      writer.use_extension("KHR_materials_transmission");
      writer.use_extension("KHR_materials_ior");
      break;
    }
  }
  if (material.is_emitter()) {
    // emissiveFactor is limited to [0, 1]; the strength carries the rest (Blender's split).
    const vec3 e = material.emission;
    const float strength = std::max({e.x, e.y, e.z, 1.0f});
    out.emissiveFactor = {e.x / strength, e.y / strength, e.z / strength};
    if (strength > 1.0f) {
      Value::Object emissive;
      emissive["emissiveStrength"] = number(strength);
      out.extensions["KHR_materials_emissive_strength"] = Value(emissive);
      writer.use_extension("KHR_materials_emissive_strength");
    }
    // Its light group (gltf_light_groups.h), as the loader reads it back: an engine scales
    // this emitter with the group's weight.
    if (!material.light_group.empty()) {
      Value::Object extras;
      extras["lightbake_group"] = Value(material.light_group);
      out.extras = Value(extras);
    }
  }
  // Cut-outs and stochastic transparency come back as they were read (docs/gltf.md, "Alpha").
  if (material.alpha_mask || material.alpha_blend) {
    pbr.baseColorFactor[3] = material.alpha_factor;
    out.alphaMode = material.alpha_mask ? "MASK" : "BLEND";
    if (material.alpha_mask) out.alphaCutoff = material.alpha_cutoff;
  }
  // The round trip keeps the back (its light and its reflection).
  if (material.two_sided_emission || material.two_sided_reflection) out.doubleSided = true;
  return out;
}

// zfar: glTF's infinite projection is written by tinygltf as zfar = 0, which is invalid; so a
// finite far plane that holds the whole scene from the camera, with margin.
void add_camera(const Camera& camera, const Bounds& bounds, Writer& writer, tinygltf::Node& root) {
  tinygltf::Camera out;
  out.name = valid_utf8(camera.name);
  out.type = "perspective";
  out.perspective.yfov = glm::radians(double(camera.vertical_fov_deg));
  out.perspective.znear = 0.01;  // m
  const vec3 centre = bounds.empty() ? camera.position : 0.5f * (bounds.min + bounds.max);
  out.perspective.zfar =
      std::max(10.0, 2.0 * double(glm::length(centre - camera.position) + bounds.diagonal()));
  Value::Object extras;
  extras["lightbake_aperture_radius_m"] = number(camera.aperture_radius);
  extras["lightbake_focus_distance_m"] = number(camera.focus_distance);
  extras["lightbake_exposure_stops"] = number(camera.exposure);
  out.extras = Value(extras);
  writer.model.cameras.push_back(out);

  // glTF cameras look down their local -Z with +Y up.
  const vec3 forward = glm::normalize(camera.target - camera.position);
  vec3 right = glm::cross(forward, camera.up);
  if (glm::length(right) < 1e-6f) right = glm::cross(forward, vec3(1.0f, 0.0f, 0.0f));
  right = glm::normalize(right);
  const vec3 up = glm::cross(right, forward);
  const glm::quat q = glm::quat_cast(glm::mat3(right, up, -forward));
  tinygltf::Node node;
  node.name = valid_utf8(camera.name);
  node.camera = int(writer.model.cameras.size() - 1);
  node.translation = {camera.position.x, camera.position.y, camera.position.z};
  node.rotation = {q.x, q.y, q.z, q.w};
  writer.model.nodes.push_back(node);
  root.children.push_back(int(writer.model.nodes.size() - 1));
}

// A lamp as KHR_lights_punctual: colour times intensity in cd (point, spot) or lx
// (directional) at 683 lm/W, the colour normalised to its brightest channel; a node at its
// position turning -Z to its direction. The direct light it gives stays the engine's to draw
// (the lightmap holds its bounce light and caustics; `--contents all` its direct light too).
void add_lamp(const Lamp& lamp, Writer& writer, tinygltf::Node& root) {
  tinygltf::Light out;
  out.name = valid_utf8(lamp.name);
  out.type = lamp.kind == LampKind::point  ? "point"
             : lamp.kind == LampKind::spot ? "spot"
                                           : "directional";
  const float brightest = std::max({lamp.intensity.x, lamp.intensity.y, lamp.intensity.z});
  const vec3 colour = brightest > 0.0f ? lamp.intensity / brightest : vec3(1.0f);
  out.color = {colour.x, colour.y, colour.z};
  out.intensity = double(brightest) * kLumensPerWatt;
  out.range = double(lamp.range);
  if (lamp.kind == LampKind::spot) {
    out.spot.innerConeAngle = double(lamp.inner_cone);
    out.spot.outerConeAngle = double(lamp.outer_cone);
  }
  writer.model.lights.push_back(out);
  tinygltf::Node node;
  node.name = valid_utf8(lamp.name);
  node.translation = {lamp.position.x, lamp.position.y, lamp.position.z};
  const glm::quat q = glm::quat(vec3(0.0f, 0.0f, -1.0f), lamp.direction);
  node.rotation = {q.x, q.y, q.z, q.w};
  Value::Object extension;
  extension["light"] = Value(int(writer.model.lights.size() - 1));
  node.extensions["KHR_lights_punctual"] = Value(extension);
  if (!lamp.light_group.empty()) {  // as on an emitter's material
    Value::Object extras;
    extras["lightbake_group"] = Value(lamp.light_group);
    node.extras = Value(extras);
  }
  writer.model.nodes.push_back(node);
  root.children.push_back(int(writer.model.nodes.size() - 1));
}

// The RGBM map's KTX2 levels (rgbm_block_levels: one m per 4x4 block, its own mip chain in
// linear light) as PNG files for the encoder.
std::vector<std::vector<unsigned char>> rgbm_block_pngs(const LightmapPng& map,
                                                        const std::vector<vec3>& radiance,
                                                        bool mipmaps) {
  std::vector<std::vector<unsigned char>> pngs;
  for (const RgbmLevel& level :
       rgbm_block_levels(map.width, map.height, radiance, map.scale, mipmaps))
    pngs.push_back(encode_png(level.width, level.height, 4, level.rgba));
  return pngs;
}

}  // namespace

// ---- the lightmap ----------------------------------------------------------------------------

Image lightmap_image(int width, int height, const std::vector<vec3>& radiance) {
  Image image(width, height, 3);
  for (size_t i = 0; i < radiance.size() && i * 3 + 2 < image.pixels.size(); ++i)
    for (int c = 0; c < 3; ++c) image.pixels[i * 3 + size_t(c)] = radiance[i][c];
  return image;
}

LightmapPng encode_lightmap_png(int width, int height, const std::vector<vec3>& radiance,
                                LightmapEncoding encoding) {
  LightmapPng out;
  out.width = width;
  out.height = height;
  out.encoding = encoding;
  out.channels = encoding == LightmapEncoding::rgbm ? 4 : 3;
  if (width <= 0 || height <= 0) return out;
  float largest = 0.0f;
  for (const vec3& r : radiance) largest = std::max({largest, r.x, r.y, r.z});
  out.scale = largest > 0.0f ? largest : 1.0f;
  const size_t channels = size_t(out.channels);
  out.bytes.resize(radiance.size() * channels);
  for (size_t i = 0; i < radiance.size(); ++i) {
    const vec3 unit = glm::clamp(radiance[i] / out.scale, vec3(0.0f), vec3(1.0f));
    uint8_t* texel = &out.bytes[i * channels];
    if (encoding == LightmapEncoding::srgb) {
      for (int c = 0; c < 3; ++c) texel[c] = unit_to_byte(srgb_oetf(unit[c]));
      continue;
    }
    const float top = std::max({unit.x, unit.y, unit.z});
    const int m = std::clamp(int(std::ceil(top * 255.0f)), 1, 255);
    for (int c = 0; c < 3; ++c) texel[c] = unit_to_byte(unit[c] * 255.0f / float(m));
    texel[3] = uint8_t(m);
  }
  out.png = encode_png(out.width, out.height, out.channels, out.bytes);
  return out;
}

vec3 decode_lightmap_texel(const uint8_t* texel, LightmapEncoding encoding, float scale) {
  vec3 value;
  for (int c = 0; c < 3; ++c)
    value[c] = encoding == LightmapEncoding::srgb
                   ? srgb_eotf(float(texel[c]) / 255.0f) * scale
                   : float(texel[c]) / 255.0f * (float(texel[3]) / 255.0f) * scale;
  return value;
}

const char* to_string(LightmapEncoding encoding) {
  return encoding == LightmapEncoding::rgbm ? "rgbm" : "srgb";
}

LightmapEncoding parse_lightmap_encoding(const std::string& text) {
  if (text == "srgb") return LightmapEncoding::srgb;
  if (text == "rgbm") return LightmapEncoding::rgbm;
  throw std::invalid_argument("--lightmap-encoding '" + text + "': expected 'srgb' or 'rgbm'");
}

const char* to_string(LightmapFormat format) {
  return format == LightmapFormat::hdr ? "hdr" : format == LightmapFormat::both ? "both" : "exr";
}

LightmapFormat parse_lightmap_format(const std::string& text) {
  if (text == "exr") return LightmapFormat::exr;
  if (text == "hdr") return LightmapFormat::hdr;
  if (text == "both") return LightmapFormat::both;
  throw std::invalid_argument("--lightmap-format '" + text + "': expected exr, hdr or both");
}

// ---- the model -------------------------------------------------------------------------------

// KTX2 with mips (below) wants the map's sides in multiples of 4: the maps grow at their far
// ends by copies of their last column and row (what CLAMP_TO_EDGE read there), and the meshes'
// lightmap UVs shrink to match (export_gltf_bytes), so every read is the same texel's.
template <class Maps>
void pad_to_multiples_of_4(Maps& maps) {
  const int width = maps.width, height = maps.height;
  const int wide = (width + 3) / 4 * 4, high = (height + 3) / 4 * 4;
  if (wide == width && high == height) return;
  auto pad = [&](auto& texels) {
    if (texels.size() != size_t(width) * size_t(height)) return;
    auto padded = texels;
    padded.resize(size_t(wide) * size_t(high));
    for (int j = 0; j < high; ++j)
      for (int i = 0; i < wide; ++i)
        padded[size_t(j) * size_t(wide) + size_t(i)] = texels[size_t(std::min(j, height - 1)) *
                                                                  size_t(width) +
                                                              size_t(std::min(i, width - 1))];
    texels = std::move(padded);
  };
  if constexpr (std::is_same_v<Maps, Lightmap>) {
    pad(maps.radiance), pad(maps.soft), pad(maps.direct), pad(maps.direct_term);
  } else {
    for (auto& axis : maps.l1) pad(axis);
    pad(maps.share);
  }
  maps.width = wide;
  maps.height = high;
}

std::vector<unsigned char> export_gltf_bytes(const Scene& scene, const BakeResult& bake,
                                             const Lightmap& lightmap,
                                             const GltfExportOptions& options,
                                             GltfExportInfo* info_out) {
  const IlluminationMaps& maps = bake.illumination;
  GltfExportInfo info;
  info.contents = options.contents;
  info.texel_density = texel_density(maps.texel_size);
  Writer writer;
  tinygltf::Model& model = writer.model;
  model.asset.version = "2.0";
  model.asset.generator = kGenerator;
  {
    Value::Object extras;
    extras["lightbake_units"] = Value(std::string(kUnits));
    extras["lightbake_convention"] = Value(std::string(kConvention));
    extras["lightbake_lightmap_contents"] = Value(std::string(to_string(options.contents)));
    extras["lightbake_texel_density_per_m"] = number(info.texel_density);
    extras["lightbake_seed"] = number(double(bake.seed));
    model.asset.extras = Value(extras);
  }
  model.buffers.resize(1);

  // Textures, each once, in scene order.
  auto usable = [&](int t) {
    return t >= 0 && size_t(t) < scene.textures.size() && scene.textures[size_t(t)].width > 0 &&
           scene.textures[size_t(t)].height > 0 && !scene.textures[size_t(t)].texels.empty();
  };
  // glTF's alpha is the base colour texture's: diffuse materials only, whose base colour
  // texture the loader reads.
  auto alpha_in_base_colour = [&](const Material& material) {
    return (material.alpha_mask || material.alpha_blend) &&
           material.kind == MaterialKind::diffuse && usable(material.alpha_texture);
  };
  std::vector<int> texture_of(scene.textures.size(), -1);
  std::map<std::tuple<TextureFilter, TextureWrap, TextureWrap>, int> sampler_of;
  auto gl_wrap = [](TextureWrap wrap) {
    return wrap == TextureWrap::clamp    ? TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE
           : wrap == TextureWrap::mirror ? TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT
                                         : TINYGLTF_TEXTURE_WRAP_REPEAT;
  };
  auto sampler_for = [&](const Texture& texture) {  // glTF's sampler of a scene texture
    const auto key = std::make_tuple(texture.filter, texture.wrap_u, texture.wrap_v);
    auto sampler = sampler_of.find(key);
    if (sampler == sampler_of.end())
      sampler = sampler_of
                    .emplace(key, writer.add_sampler(gl_wrap(texture.wrap_u),
                                                     texture.filter == TextureFilter::nearest,
                                                     gl_wrap(texture.wrap_v)))
                    .first;
    return sampler->second;
  };
  auto add_texture = [&](const Texture& texture) {
    const std::string name = fs::path(texture.path).stem().string();
    return writer.add_texture(writer.add_png_image(name, texture_png(texture)),
                              sampler_for(texture));
  };
  for (const Material& material : scene.materials)
    for (int t : {alpha_in_base_colour(material) ? -1 : material.reflectance_texture,
                  material.bump == BumpKind::normal_map ? material.bump_texture : -1})
      if (usable(t) && texture_of[size_t(t)] < 0)
        texture_of[size_t(t)] = add_texture(scene.textures[size_t(t)]);
  // Base colours with their alpha, once per (colour, alpha) pair.
  std::vector<int> base_colour_with_alpha_of(scene.materials.size(), -1);
  std::map<std::pair<int, int>, int> with_alpha_texture;
  for (size_t mi = 0; mi < scene.materials.size(); ++mi) {
    const Material& material = scene.materials[mi];
    if (!alpha_in_base_colour(material)) continue;
    const int colour = usable(material.reflectance_texture) ? material.reflectance_texture : -1;
    const auto key = std::make_pair(colour, material.alpha_texture);
    auto found = with_alpha_texture.find(key);
    if (found == with_alpha_texture.end())
      found = with_alpha_texture
                  .emplace(key, add_texture(base_colour_with_alpha(
                                    colour >= 0 ? &scene.textures[size_t(colour)] : nullptr,
                                    scene.textures[size_t(material.alpha_texture)])))
                  .first;
    base_colour_with_alpha_of[mi] = found->second;
  }

  // Height bumps as normal maps, one per material (glTF has no height bump).
  std::vector<int> height_normal_of(scene.materials.size(), -1);
  for (size_t mi = 0; mi < scene.materials.size(); ++mi) {
    const Material& material = scene.materials[mi];
    const int t = material.bump_texture;
    if (material.kind != MaterialKind::diffuse || material.bump != BumpKind::height || t < 0 ||
        size_t(t) >= scene.textures.size())
      continue;
    const Texture& height = scene.textures[size_t(t)];
    const UvFrame frame = uv_frame(scene, int(mi));
    if (height.width <= 0 || height.height <= 0 || height.texels.empty() ||
        !(frame.metres.x > 0.0f && frame.metres.y > 0.0f))
      continue;
    const int sampler = sampler_for(height);
    height_normal_of[mi] = writer.add_texture(
        writer.add_png_image(fs::path(height.path).stem().string() + "_normal",
                             texture_png(height_to_normal_map(height, material.bump_scale,
                                                              frame))),
        sampler);
  }

  // The lightmap, once for the whole file.
  const LightmapPng map =
      encode_lightmap_png(lightmap.width, lightmap.height, lightmap.radiance, options.encoding);
  int lightmap_texture = -1;
  int directional_textures[3] = {-1, -1, -1};
  Value::Array group_layers;  // LIGHTBAKE_lightmap_groups's layers
  if (!map.png.empty()) {
    const int sampler = writer.add_sampler(TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE);
    model.samplers[size_t(sampler)].minFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;  // charts bleed
    lightmap_texture = writer.add_texture(writer.add_png_image("lightmap", map.png), sampler);
    if (!options.ktx2_encoder.empty()) {
      // The same light as KTX2 (ktx2_encode.h), the PNG staying the texture's fallback source.
      // Mips only where WebGL takes them: a BC7/S3TC texture with levels needs a base whose
      // sides are multiples of 4 (ANGLE refuses the storage otherwise, and the map draws black).
      const bool mipmaps = map.width % 4 == 0 && map.height % 4 == 0;
      const std::vector<unsigned char> ktx2 =
          map.encoding == LightmapEncoding::srgb
              ? encode_ktx2(options.ktx2_encoder, map.png, mipmaps)
              : encode_ktx2_levels(options.ktx2_encoder,
                                   rgbm_block_pngs(map, lightmap.radiance, mipmaps));
      Value::Object basisu;
      basisu["source"] = Value(writer.add_image("lightmap_ktx2", ktx2, "image/ktx2"));
      model.textures[size_t(lightmap_texture)].extensions["KHR_texture_basisu"] =
          Value(std::move(basisu));
      writer.use_extension("KHR_texture_basisu");
      // With its mip chain the engine samples it with a mip filter (and builds the PNG
      // fallback's chain the same way).
      if (mipmaps)
        model.samplers[size_t(sampler)].minFilter = TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR;
      info.ktx2_bytes = ktx2.size();
      info.ktx2_mipmaps = mipmaps;
    }
    info.png_bytes = map.png.size();
    if (const DirectionalMaps* band = options.directional_maps) {
      const char* names[3] = {"lightmap_l1_x", "lightmap_l1_y", "lightmap_l1_z"};
      const auto with_share = [&](size_t axis) { return axis == 0 && options.directional_share; };
      for (size_t a = 0; a < 3; ++a)
        directional_textures[a] = writer.add_texture(
            writer.add_png_image(
                names[a],
                encode_png(map.width, map.height, with_share(a) ? 4 : 3,
                           encode_l1_ratios(lightmap.radiance, band->l1[a],
                                            with_share(a) ? &band->share : nullptr))),
            sampler);
      info.directional = true;
    }
    if (options.group_lightmaps) {
      for (size_t g = 0; g < options.group_lightmaps->size(); ++g) {
        const Lightmap& group = (*options.group_lightmaps)[g];
        const LightmapPng layer =
            encode_lightmap_png(group.width, group.height, group.radiance, options.encoding);
        Value::Object binding;
        binding["name"] = Value(bake.light_groups.at(g));
        binding["weight"] = number(1.0);
        binding["index"] = Value(writer.add_texture(
            writer.add_png_image("lightmap_group" + std::to_string(g + 1), layer.png), sampler));
        binding["texCoord"] = Value(1);
        binding["intensity"] = number(glm::pi<double>() * layer.scale);
        group_layers.push_back(Value(binding));
      }
      info.group_layers = group_layers.size();
    }
    info.map_width = map.width;
    info.map_height = map.height;
    info.map_scale = map.scale;
  }

  // Materials: one per (scene material, has lightmap), since MOZ_lightmap reads TEXCOORD_1
  // and meshes without a map have none.
  std::map<std::pair<int, bool>, int> material_of;
  auto gltf_material = [&](int index, bool lightmapped) {
    const auto key = std::make_pair(index, lightmapped);
    if (auto found = material_of.find(key); found != material_of.end()) return found->second;
    const Material fallback;
    const Material& material = index >= 0 && size_t(index) < scene.materials.size()
                                   ? scene.materials[size_t(index)]
                                   : fallback;
    const bool listed = index >= 0 && size_t(index) < scene.materials.size();
    tinygltf::Material out =
        make_material(material, writer, texture_of, listed ? height_normal_of[size_t(index)] : -1,
                      listed ? base_colour_with_alpha_of[size_t(index)] : -1);
    if (lightmapped) {
      Value::Object moz;
      moz["index"] = Value(lightmap_texture);
      moz["texCoord"] = Value(1);
      moz["intensity"] = number(glm::pi<double>() * map.scale);
      out.extensions["MOZ_lightmap"] = Value(moz);
      writer.use_extension("MOZ_lightmap");
      Value::Object extras =
          out.extras.IsObject() ? out.extras.Get<Value::Object>() : Value::Object();
      extras["lightbake_lightmap"] = lightmap_extras(map, options, info.texel_density);
      out.extras = Value(extras);
      if (directional_textures[0] >= 0) {
        Value::Array l1;
        for (int texture : directional_textures) {
          Value::Object binding;
          binding["index"] = Value(texture);
          binding["texCoord"] = Value(1);
          l1.push_back(Value(binding));
        }
        Value::Object band;
        band["l1"] = Value(l1);
        band["encoding"] = Value(std::string("ratio8"));
        band["space"] = Value(std::string("world"));
        band["share"] = Value(options.directional_share);  // s in the x map's alpha
        out.extensions[kDirectionalExtension] = Value(band);
        writer.use_extension(kDirectionalExtension);
      }
      if (!group_layers.empty()) {
        Value::Object groups;
        groups["layers"] = Value(group_layers);
        out.extensions[kLightGroupsExtension] = Value(groups);
        writer.use_extension(kLightGroupsExtension);
      }
    }
    model.materials.push_back(out);
    return material_of[key] = int(model.materials.size() - 1);
  };

  tinygltf::Node root;
  root.name = "lightbake";
  const glm::dvec3 origin = scene.world_origin;
  if (origin != glm::dvec3(0.0)) root.translation = {origin.x, origin.y, origin.z};
  std::vector<tinygltf::Node> mesh_nodes;

  // One glTF mesh and node per scene mesh; `m` its index in scene.meshes, or -1 for a moving
  // object (Scene::dynamic_meshes: no map, `extras.dynamic`, its probe light).
  auto add_mesh = [&](const Mesh& mesh, int m, const ShL2* probe_sh) {
    if (mesh.positions.empty() || mesh.triangles.empty()) return;
    const size_t n = mesh.positions.size();
    tinygltf::Primitive primitive;
    primitive.mode = TINYGLTF_MODE_TRIANGLES;
    primitive.attributes["POSITION"] = writer.add_floats(&mesh.positions[0].x, n, 3, true);
    if (mesh.normals.size() == n) {
      const std::vector<vec3> normals = unit_normals(mesh.normals);
      primitive.attributes["NORMAL"] = writer.add_floats(&normals[0].x, n, 3);
    }
    if (mesh.tangents.size() == n) {
      const std::vector<vec4> tangents = unit_tangents(mesh.tangents);
      primitive.attributes["TANGENT"] = writer.add_floats(&tangents[0].x, n, 4);
    }
    if (mesh.uvs.size() == n)
      primitive.attributes["TEXCOORD_0"] = writer.add_floats(&mesh.uvs[0].x, n, 2);
    const size_t index = size_t(m);
    const bool has_map = m >= 0 && lightmap_texture >= 0 && index < maps.lightmap_uvs.size() &&
                         !maps.lightmap_uvs[index].empty() && mesh.lightmap_uvs.size() == n;
    // Scene-given TEXCOORD_1 on a mesh without a map is kept: it is the user's. glTF wants
    // TEXCOORD_n numbered from 0, so a mesh without texture coordinates gets the lightmap UVs
    // as TEXCOORD_0 too (no texture of its material reads them).
    if (mesh.lightmap_uvs.size() == n) {
      std::vector<vec2> uvs = mesh.lightmap_uvs;
      if (has_map && (lightmap.width != maps.width || lightmap.height != maps.height))
        for (vec2& uv : uvs)  // the map grew to sides in multiples of 4 (pad_to_multiples_of_4)
          uv *= vec2(float(maps.width) / float(lightmap.width),
                     float(maps.height) / float(lightmap.height));
      const int lightmap_uvs = writer.add_floats(&uvs[0].x, n, 2);
      primitive.attributes["TEXCOORD_1"] = lightmap_uvs;
      if (mesh.uvs.size() != n) primitive.attributes["TEXCOORD_0"] = lightmap_uvs;
    }
    primitive.indices = writer.add_indices(mesh.triangles);
    primitive.material = gltf_material(mesh.material, has_map);
    if (has_map) ++info.lightmapped_meshes;

    tinygltf::Mesh out;
    out.name = valid_utf8(mesh.name);
    out.primitives.push_back(primitive);
    model.meshes.push_back(out);
    tinygltf::Node node;
    node.name = valid_utf8(mesh.name);
    node.mesh = int(model.meshes.size() - 1);
    if (has_map && index < maps.mesh_texel_size.size()) {
      Value::Object extras;
      extras["lightbake_texel_density_per_m"] = number(texel_density(maps.mesh_texel_size[index]));
      node.extras = Value(extras);
    }
    if (m < 0) {
      Value::Object extras;
      extras["dynamic"] = Value(true);
      if (probe_sh) extras["lightbake_probe_sh"] = sh_value(*probe_sh);
      node.extras = Value(extras);
    }
    mesh_nodes.push_back(node);
    ++info.meshes;
    info.triangles += mesh.triangles.size();
    info.vertices += n;
  };
  for (size_t m = 0; m < scene.meshes.size(); ++m)
    add_mesh(mesh_with_lightmap(scene.meshes[m], maps, m), int(m), nullptr);
  for (size_t d = 0; d < scene.dynamic_meshes.size(); ++d) {
    const bool lit = options.dynamic_sh && d < options.dynamic_sh->size();
    add_mesh(scene.dynamic_meshes[d], -1, lit ? &(*options.dynamic_sh)[d] : nullptr);
  }
  for (tinygltf::Node& node : mesh_nodes) {
    model.nodes.push_back(std::move(node));
    root.children.push_back(int(model.nodes.size() - 1));
  }
  const Bounds bounds = scene_bounds(scene);
  for (const Camera& camera : scene.cameras) add_camera(camera, bounds, writer, root);
  for (const Lamp& lamp : scene.lights) add_lamp(lamp, writer, root);
  model.nodes.push_back(root);
  tinygltf::Scene gltf_scene;
  gltf_scene.name = valid_utf8(fs::path(scene.source_path).stem().string());
  gltf_scene.nodes.push_back(int(model.nodes.size() - 1));
  if (options.light_probes && !options.light_probes->empty()) {
    gltf_scene.extensions[kLightProbesExtension] = probe_grid_value(*options.light_probes);
    writer.use_extension(kLightProbesExtension);
  }
  model.scenes.push_back(gltf_scene);
  model.defaultScene = 0;
  model.buffers[0].data.shrink_to_fit();
  if (model.buffers[0].data.empty()) model.buffers.clear();

  std::ostringstream stream;
  tinygltf::TinyGLTF gltf;
  if (!gltf.WriteGltfSceneToStream(&model, stream, /*prettyPrint=*/!options.binary, options.binary))
    throw std::runtime_error("glTF serialisation failed");
  const std::string text = stream.str();
  info.bytes = text.size();
  if (info_out) *info_out = info;
  return std::vector<unsigned char>(text.begin(), text.end());
}

std::string lightmap_exr_path(const std::string& gltf_path) {
  fs::path path(gltf_path);
  return (path.parent_path() / (path.stem().string() + ".lightmap.exr")).string();
}

std::string lightmap_hdr_path(const std::string& gltf_path) {
  fs::path path(gltf_path);
  return (path.parent_path() / (path.stem().string() + ".lightmap.hdr")).string();
}

std::vector<std::string> export_paths(const std::string& gltf_path,
                                      const GltfExportOptions& options) {
  std::vector<std::string> paths = {gltf_path};
  if (options.format != LightmapFormat::hdr) paths.push_back(lightmap_exr_path(gltf_path));
  if (options.format != LightmapFormat::exr) paths.push_back(lightmap_hdr_path(gltf_path));
  return paths;
}

double export_files_bytes(const Scene& scene, int atlas_width, int atlas_height,
                          const std::string& gltf_path, const GltfExportOptions& options) {
  constexpr double kExrTexelBytes = 16.0, kHdrTexelBytes = 4.0, kEightBitTexelBytes = 4.0;
  constexpr double kTriangleBytes = 128.0, kJsonBytes = 1 << 20;
  const double groups = double(light_group_names(scene).size());  // at most: weights merge them
  const double maps = 1.0 + groups + (options.directional ? 3.0 : 0.0);
  const double inside = (options.ktx2_encoder.empty() ? 1.0 : 2.0) * kEightBitTexelBytes;
  const double base64 = fs::path(gltf_path).extension() == ".gltf" ? 4.0 / 3.0 : 1.0;
  const double per_texel = kExrTexelBytes + kHdrTexelBytes + base64 * inside;
  return maps * per_texel * double(atlas_width) * double(atlas_height) +
         base64 * kTriangleBytes * double(triangle_count(scene)) + kJsonBytes;
}

GltfExportInfo export_gltf(const std::string& path, const Scene& scene, const BakeResult& bake,
                           const GltfExportOptions& options_in, const Progress& progress) {
  const std::string extension = fs::path(path).extension().string();
  if (extension != ".glb" && extension != ".gltf")
    throw std::runtime_error(path + ": output must be .glb or .gltf");
  const fs::path parent = fs::path(path).parent_path();
  if (!parent.empty() && !fs::is_directory(parent))
    throw std::runtime_error(path + ": the folder " + parent.string() + " does not exist");
  GltfExportOptions options = options_in;
  options.binary = extension == ".glb";
  options.exr_name.clear();
  options.hdr_name.clear();

  LightmapParams params;
  params.contents = options.contents;
  params.direct_side = options.direct_side;
  params.shadow_side = options.shadow_side;
  params.stitch_seams = options.stitch_seams;
  params.denoise_direct = options.denoise_direct;
  params.seed = bake.seed;
  DirectionalMaps band;
  if (options.directional ? options.direct_light != nullptr : options.direct_band != nullptr)
    throw std::runtime_error(path + ": directional maps take the direct term with its band "
                                    "(direct_band), plain ones without (direct_light)");
  Lightmap lightmap =
      options.directional
          ? bake_directional_lightmap(scene, bake, params, options.directional_params, band,
                                      progress, options.direct_band)
          : bake_lightmap(scene, bake, params, progress, options.direct_light,
                          options.direct_unshadowed);
  if (options.directional) options.directional_maps = &band;
  // Light groups: a layer each, their maps made as the whole one was (direct term included).
  std::vector<Lightmap> group_maps;
  if (!bake.light_groups.empty()) {
    if (options.directional || options.direct_light)
      throw std::runtime_error(path + ": light groups' layers go without --directional and "
                                      "export shards; give --group-weights for one fixed mix");
    group_maps = bake_group_lightmaps(scene, bake, params, progress);
    options.group_lightmaps = &group_maps;
  }
  if (!options.ktx2_encoder.empty()) {
    pad_to_multiples_of_4(lightmap);
    if (options.directional) pad_to_multiples_of_4(band);
    for (Lightmap& group : group_maps) pad_to_multiples_of_4(group);
  }
  const bool has_map = lightmap.width > 0 && lightmap.height > 0;
  const std::string exr_path = lightmap_exr_path(path), hdr_path = lightmap_hdr_path(path);
  const bool exr = has_map && options.format != LightmapFormat::hdr;
  const bool hdr = has_map && options.format != LightmapFormat::exr;
  GltfExportInfo info;
  progress.throw_if_cancelled();

  // Every file complete under a temporary name before any is renamed into place; the maps
  // first, so the glTF can record their hashes: a reader told by the glTF which EXR to read
  // knows another export's EXR (two exports to one name) from this one's. The glTF is renamed
  // last: until then readers see the old glTF, which names the old maps' hashes.
  std::vector<std::pair<std::string, std::string>> staged;  // temporary, final
  std::vector<std::pair<std::string, FileIdentity>> published;  // this run's files
  auto undo = [&] {
    std::error_code ec;
    for (const auto& [temp, final_path] : staged) fs::remove(temp, ec);
    for (const auto& [final_path, mine] : published) remove_if_same_file(final_path, mine);
  };
  try {
    const Image image =
        has_map ? lightmap_image(lightmap.width, lightmap.height, lightmap.radiance) : Image();
    if (exr) {
      staged.emplace_back(temp_sibling_path(exr_path), exr_path);
      write_exr(staged.back().first, image, ExrPixelType::half);
      options.exr_name = fs::path(exr_path).filename().string();
      options.exr_fnv1a = file_fnv1a_hex(staged.back().first);
    }
    if (hdr) {
      staged.emplace_back(temp_sibling_path(hdr_path), hdr_path);
      write_hdr(staged.back().first, image);
      options.hdr_name = fs::path(hdr_path).filename().string();
      options.hdr_fnv1a = file_fnv1a_hex(staged.back().first);
    }
    const std::vector<unsigned char> bytes =
        export_gltf_bytes(scene, bake, lightmap, options, &info);
    info.shadow_rays = lightmap.shadow_rays;
    info.denoised = lightmap.denoised;
    info.denoise = lightmap.denoise;
    info.lightmap_seconds = lightmap.seconds + band.seconds;
    for (const Lightmap& group : group_maps) info.lightmap_seconds += group.seconds;
    info.directional_seconds = band.seconds;
    staged.emplace_back(temp_sibling_path(path), path);
    {
      errno = 0;  // what the failing write left says why (EFBIG, ENOSPC)
      std::ofstream out(staged.back().first, std::ios::binary);
      out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
      out.close();
      if (!out)
        throw std::runtime_error(path + ": cannot write: " +
                                 (errno != 0 ? std::strerror(errno) : "write error"));
    }
    for (const auto& [temp, final_path] : staged) {
      const std::optional<FileIdentity> mine = file_identity(temp);
      if (!mine) throw std::runtime_error(final_path + ": cannot write: " + std::strerror(errno));
      std::error_code ec;
      fs::rename(temp, final_path, ec);
      if (ec) throw std::runtime_error(final_path + ": cannot write: " + ec.message());
      published.emplace_back(final_path, *mine);
    }
    staged.clear();
  } catch (...) {
    undo();
    rethrow_naming(staged);
  }
  // The glTF first, as before: callers name it as the export's main file.
  info.files.push_back(path);
  for (const auto& [final_path, mine] : published)
    if (final_path != path) info.files.push_back(final_path);
  return info;
}

bool is_lightbake_gltf(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::string head(12, '\0');
  in.read(head.data(), 12);
  std::string json_text;
  if (in.gcount() == 12 && head.compare(0, 4, "glTF") == 0) {
    uint32_t chunk[2] = {0, 0};  // length, type
    in.read(reinterpret_cast<char*>(chunk), sizeof(chunk));
    if (!in || chunk[1] != 0x4E4F534Au || chunk[0] > (64u << 20)) return false;  // "JSON"
    json_text.resize(chunk[0]);
    in.read(json_text.data(), std::streamsize(chunk[0]));
    if (!in) return false;
  } else {
    in.clear();
    in.seekg(0);
    json_text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  const nlohmann::json json = nlohmann::json::parse(json_text, nullptr, false);
  if (!json.is_object() || !json.contains("asset") || !json["asset"].is_object()) return false;
  const nlohmann::json generator = json["asset"].value("generator", nlohmann::json());
  return generator.is_string() && generator.get<std::string>().rfind(kGenerator, 0) == 0;
}

}  // namespace lb
