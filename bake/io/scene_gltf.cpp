// glTF 2.0 (.gltf + .bin + images, .glb) -> lb::Scene, as Blender exports it.
// The mapping from glTF materials to lightbake materials, the emission scale and every warning
// are documented in docs/gltf.md; keep the two in step.

#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <iterator>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <tuple>

#include "bake/io/gltf_directional.h"
#include "bake/io/ktx2_encode.h"
#include "bake/io/gltf_precheck.h"
#include "bake/io/image_codecs.h"
#include "bake/io/image_io.h"
#include "bake/io/input_limits.h"
#include "bake/io/scene_load.h"
#include "bake/io/scene_validate.h"
#include "bake/io/uv_transform.h"
#include "bake/tangent_space.h"

namespace lb {

namespace {

namespace fs = std::filesystem;
using glm::dmat4;
using glm::mat3;
using glm::mat4;

// Below this roughness a metal is a perfect mirror (GGX alpha = 0.05^2 = 0.0025 is already
// indistinguishable from a mirror at lightmap resolution).
constexpr double kMirrorRoughness = 0.05;
// A metallic factor at or above this is a metal, below it a dielectric (diffuse).
constexpr double kMetallicThreshold = 0.5;
// A transmission factor above this is glass.
constexpr double kTransmissionThreshold = 0.5;

// Extensions whose meaning we honour (fully or as documented in docs/gltf.md).
// KHR_mesh_quantization only widens the accessor types allowed, which read_accessor handles.
const std::set<std::string> kSupportedExtensions = {
    "KHR_materials_transmission", "KHR_materials_ior",     "KHR_materials_emissive_strength",
    "KHR_mesh_quantization",      "KHR_texture_transform", "KHR_lights_punctual",
    "KHR_texture_basisu"};  // honoured by reading the texture's fallback `source`
// Extensions that are safe to ignore with a warning even when required: the geometry is intact.
const std::set<std::string> kIgnorableExtensions = {"KHR_animation_pointer",
                                                    "KHR_materials_unlit",
                                                    "KHR_materials_volume",
                                                    "KHR_materials_specular",
                                                    "KHR_materials_clearcoat",
                                                    "KHR_materials_sheen",
                                                    "KHR_materials_variants",
                                                    "KHR_materials_iridescence",
                                                    "KHR_materials_anisotropy",
                                                    "KHR_materials_dispersion",
                                                    "EXT_texture_webp",
                                                    "KHR_materials_pbrSpecularGlossiness"};

std::string one_line(std::string text) {
  std::string result;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
    if (line.empty()) continue;
    if (!result.empty()) result += "; ";
    result += line;
  }
  return result;
}

// ---------------------------------------------------------------------------------------------
// Loader state: the model, the file name for messages, warnings without repeats.

struct Loader {
  std::string path;
  tinygltf::Model model;
  Scene scene;
  std::vector<std::string> warnings;
  std::set<std::string> warned;
  // (image, srgb, alpha alone) -> scene texture
  std::map<std::tuple<int, int, bool, bool>, int> texture_of_image;  // image, sampler, ...
  std::vector<bool> image_failed;                        // decode failures, already warned
  int default_material = -1;
  // A file `lightbake export` wrote: its MOZ_lightmap and COLOR_0 are the baked light, read by
  // read_gltf_bake (gltf_bake_read.h), not ignored, so they draw no warning.
  bool lightbake_export = false;

  [[noreturn]] void fail(const std::string& place, const std::string& message) const {
    throw SceneError(path + ": at " + place + ": " + message);
  }
  void warn(const std::string& place, const std::string& message) {
    std::string line = path + ": at " + place + ": " + message;
    if (warned.insert(line).second) warnings.push_back(std::move(line));
  }
  // An unsupported extension is reported where it is first used, once per extension name.
  void warn_extension(const std::string& place, const std::string& name,
                      const std::string& message) {
    if (warned_extensions.insert(name).second) warn(place, message);
  }
  std::set<std::string> warned_extensions;

  // Things skipped once per element, reported once per file with their count and first place.
  struct Skipped {
    size_t count = 0;
    std::string first_place;
    void note(const std::string& place) {
      if (count++ == 0) first_place = place;
    }
  };
  Skipped skins, morph_targets;
  // Per glTF material: the UV set and KHR_texture_transform its textures are sampled with.
  std::vector<UvTransform> material_uvs;
};

// Images are decoded by OpenImageIO (image_codecs.h), as every image the tool reads; a failure
// becomes a warning (the material keeps its factor) instead of failing the whole load as
// tinygltf would by default.
struct ImageDecodeLog {
  std::vector<std::pair<int, std::string>> failures;  // image index, reason
};

bool is_png_data(const unsigned char* bytes, int size) {
  static const unsigned char kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  return size >= 8 && std::memcmp(bytes, kSignature, 8) == 0;
}

// The size a PNG's header claims (big-endian width and height in IHDR), or 0 x 0.
std::pair<uint64_t, uint64_t> png_claimed_size(const unsigned char* bytes, int size) {
  if (size < 24 || !is_png_data(bytes, size)) return {0, 0};
  auto be32 = [&](int at) {
    return uint64_t(bytes[at]) << 24 | uint64_t(bytes[at + 1]) << 16 |
           uint64_t(bytes[at + 2]) << 8 | uint64_t(bytes[at + 3]);
  };
  return {be32(16), be32(20)};
}

bool decode_image_or_note(tinygltf::Image* image, const int image_index, std::string* err,
                          std::string* warn, int req_width, int req_height,
                          const unsigned char* bytes, int size, void* user_data) {
  (void)err, (void)warn, (void)req_width, (void)req_height;
  auto* log = static_cast<ImageDecodeLog*>(user_data);
  if (is_ktx2_data(bytes, size_t(std::max(size, 0)))) return true;  // the PNG fallback is read
  auto fail = [&](const std::string& reason) {
    log->failures.emplace_back(image_index, reason);
    image->width = image->height = image->component = 0;
    image->image.clear();
    return true;
  };
  // A PNG's IHDR gives the size for the message; the decoder checks every format's header too.
  const auto [width, height] = png_claimed_size(bytes, size);
  if (width > 0 && height > 0 && width > limits::kMaxTextureValues / 4 / height)
    return fail("the image claims " + std::to_string(width) + " x " + std::to_string(height) +
                " pixels, more than " + std::to_string(limits::kMaxTextureValues) +
                " values (bake/io/input_limits.h)");
  codecs::Decoded decoded;
  try {
    // OpenImageIO picks its reader by the name's extension: glTF's two formats by their magic.
    const bool png = is_png_data(bytes, size);
    const bool jpeg = size >= 3 && bytes[0] == 0xff && bytes[1] == 0xd8 && bytes[2] == 0xff;
    if (!png && !jpeg) return fail("not a PNG or JPEG image (the formats glTF allows)");
    const std::string name =
        "images[" + std::to_string(image_index) + "]" + (png ? ".png" : ".jpg");
    decoded = codecs::decode({name, bytes, size_t(std::max(size, 0))}, 4,
                             limits::kMaxTextureValues);
  } catch (const std::exception& e) {
    return fail(one_line(e.what()));
  }
  // As tinygltf's own loader laid images out (RGBA, grey repeated, alpha 1 where there is
  // none), in 16 bits: an 8-bit sample k becomes k * 257, which reads back as k / 255 exactly.
  const Image& in = decoded.image;
  const int channels = in.channels;
  const bool has_alpha = decoded.alpha_channel >= 0;
  const int colour = std::max(1, has_alpha ? channels - 1 : channels);
  image->width = in.width;
  image->height = in.height;
  image->component = 4;
  image->bits = 16;
  image->pixel_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
  image->image.resize(size_t(in.width) * size_t(in.height) * 4 * 2);
  for (size_t p = 0; p < size_t(in.width) * size_t(in.height); ++p)
    for (int c = 0; c < 4; ++c) {
      const size_t base = p * size_t(channels);
      float value = 1.0f;
      if (c < 3)
        value = in.pixels[base + size_t(std::min(c, colour - 1))];
      else if (has_alpha)
        value = in.pixels[base + size_t(decoded.alpha_channel)];
      const auto sample = uint16_t(std::lround(std::clamp(value, 0.0f, 1.0f) * 65535.0f));
      std::memcpy(image->image.data() + 2 * (p * 4 + size_t(c)), &sample, 2);
    }
  return true;
}

// ---------------------------------------------------------------------------------------------
// Accessors: bounds-checked reads of any component type, strided or sparse.

int component_size(int component_type) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return 2;
    case TINYGLTF_COMPONENT_TYPE_INT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return 4;
    default:
      return 0;
  }
}

const char* type_name(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR:
      return "SCALAR";
    case TINYGLTF_TYPE_VEC2:
      return "VEC2";
    case TINYGLTF_TYPE_VEC3:
      return "VEC3";
    case TINYGLTF_TYPE_VEC4:
      return "VEC4";
    case TINYGLTF_TYPE_MAT2:
      return "MAT2";
    case TINYGLTF_TYPE_MAT3:
      return "MAT3";
    case TINYGLTF_TYPE_MAT4:
      return "MAT4";
    default:
      return "unknown";
  }
}

double read_component(const unsigned char* p, int component_type, bool normalized) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      int8_t v;
      std::memcpy(&v, p, 1);
      return normalized ? std::max(v / 127.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return normalized ? *p / 255.0 : *p;
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      int16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? std::max(v / 32767.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? v / 65535.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_INT: {
      int32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
      uint32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case TINYGLTF_COMPONENT_TYPE_FLOAT: {
      float v;
      std::memcpy(&v, p, 4);
      return v;
    }
    default:
      return 0.0;
  }
}

// A checked window onto a buffer view: `count` elements of `element_size` bytes, `stride` apart.
struct Window {
  const unsigned char* data = nullptr;
  size_t stride = 0;
};

Window checked_window(const Loader& loader, const std::string& place, int buffer_view_index,
                      size_t byte_offset, size_t count, size_t element_size, bool allow_stride) {
  const auto& model = loader.model;
  if (buffer_view_index < 0 || size_t(buffer_view_index) >= model.bufferViews.size())
    loader.fail(place, "bufferView " + std::to_string(buffer_view_index) + " out of range (" +
                           std::to_string(model.bufferViews.size()) + " buffer views)");
  const tinygltf::BufferView& view = model.bufferViews[size_t(buffer_view_index)];
  const std::string view_place = "bufferViews[" + std::to_string(buffer_view_index) + "]";
  if (view.buffer < 0 || size_t(view.buffer) >= model.buffers.size())
    loader.fail(view_place, "buffer " + std::to_string(view.buffer) + " out of range (" +
                                std::to_string(model.buffers.size()) + " buffers)");
  const size_t buffer_size = model.buffers[size_t(view.buffer)].data.size();
  if (view.byteOffset > buffer_size || view.byteLength > buffer_size - view.byteOffset)
    loader.fail(view_place, "bytes " + std::to_string(view.byteOffset) + ".." +
                                std::to_string(view.byteOffset + view.byteLength) +
                                " exceed buffer " + std::to_string(view.buffer) + " of " +
                                std::to_string(buffer_size) + " bytes");
  const size_t stride = allow_stride && view.byteStride ? view.byteStride : element_size;
  if (stride < element_size)
    loader.fail(view_place, "byteStride " + std::to_string(stride) +
                                " is smaller than an element (" + std::to_string(element_size) +
                                " bytes)");
  if (count > 0) {
    const size_t last_end = byte_offset + stride * (count - 1) + element_size;
    if (byte_offset > view.byteLength || (count - 1) > (view.byteLength / stride) ||
        last_end > view.byteLength)
      loader.fail(place, std::to_string(count) + " elements from byte " +
                             std::to_string(byte_offset) + " exceed bufferViews[" +
                             std::to_string(buffer_view_index) + "] of " +
                             std::to_string(view.byteLength) + " bytes");
  }
  return {model.buffers[size_t(view.buffer)].data.data() + view.byteOffset + byte_offset, stride};
}

// All values of an accessor as doubles, `components` per element (dense, sparse applied).
struct AccessorValues {
  size_t count = 0;
  int components = 0;
  std::vector<double> values;
  double at(size_t element, int component) const {
    return values[element * size_t(components) + size_t(component)];
  }
};

AccessorValues read_accessor(const Loader& loader, int accessor_index, const std::string& place,
                             std::initializer_list<int> allowed_types) {
  const auto& model = loader.model;
  if (accessor_index < 0 || size_t(accessor_index) >= model.accessors.size())
    loader.fail(place, "accessor " + std::to_string(accessor_index) + " out of range (" +
                           std::to_string(model.accessors.size()) + " accessors)");
  const tinygltf::Accessor& accessor = model.accessors[size_t(accessor_index)];
  const std::string where = place + " (accessors[" + std::to_string(accessor_index) + "])";
  if (std::find(allowed_types.begin(), allowed_types.end(), accessor.type) == allowed_types.end())
    loader.fail(where, std::string("unexpected type ") + type_name(accessor.type));
  const int size = component_size(accessor.componentType);
  if (size == 0)
    loader.fail(where, "unsupported componentType " + std::to_string(accessor.componentType));
  const int components = tinygltf::GetNumComponentsInType(uint32_t(accessor.type));

  AccessorValues result;
  result.count = accessor.count;
  result.components = components;
  if (accessor.bufferView >= 0) {
    const Window window = checked_window(loader, where, accessor.bufferView, accessor.byteOffset,
                                         accessor.count, size_t(size) * size_t(components), true);
    result.values.resize(accessor.count * size_t(components));
    for (size_t i = 0; i < accessor.count; ++i)
      for (int c = 0; c < components; ++c)
        result.values[i * size_t(components) + size_t(c)] =
            read_component(window.data + i * window.stride + size_t(c * size),
                           accessor.componentType, accessor.normalized);
  } else {
    // No buffer view: zeros (to be filled by sparse values). Guard absurd counts.
    if (accessor.count > (size_t(1) << 26))
      loader.fail(where, "count " + std::to_string(accessor.count) + " without a bufferView");
    result.values.assign(accessor.count * size_t(components), 0.0);
  }

  if (accessor.sparse.isSparse) {
    const auto& sparse = accessor.sparse;
    const std::string sparse_place = where + ".sparse";
    if (sparse.count < 0 || size_t(sparse.count) > accessor.count)
      loader.fail(sparse_place, "count " + std::to_string(sparse.count) +
                                    " exceeds accessor count " + std::to_string(accessor.count));
    const int index_size = component_size(sparse.indices.componentType);
    if (index_size == 0 || sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT)
      loader.fail(sparse_place + ".indices",
                  "unsupported componentType " + std::to_string(sparse.indices.componentType));
    const Window indices =
        checked_window(loader, sparse_place + ".indices", sparse.indices.bufferView,
                       size_t(std::max(sparse.indices.byteOffset, 0)), size_t(sparse.count),
                       size_t(index_size), false);
    const Window values =
        checked_window(loader, sparse_place + ".values", sparse.values.bufferView,
                       size_t(std::max(sparse.values.byteOffset, 0)), size_t(sparse.count),
                       size_t(size) * size_t(components), false);
    for (size_t k = 0; k < size_t(sparse.count); ++k) {
      const double target =
          read_component(indices.data + k * indices.stride, sparse.indices.componentType, false);
      if (target < 0 || target >= double(accessor.count))
        loader.fail(sparse_place + ".indices", "index " + std::to_string(size_t(target)) +
                                                   " out of range (" +
                                                   std::to_string(accessor.count) + " elements)");
      for (int c = 0; c < components; ++c)
        result.values[size_t(target) * size_t(components) + size_t(c)] =
            read_component(values.data + k * values.stride + size_t(c * size),
                           accessor.componentType, accessor.normalized);
    }
  }
  return result;
}

// ---------------------------------------------------------------------------------------------
// Textures: glTF images -> lb::Texture (sRGB decoded for colour, as stored for data maps).

// glTF's sampler: magFilter NEAREST reads the nearest texel (Blender's Closest), anything else
// blends (minFilter only chooses mipmaps, which a ray tracer does not use); wrapS / wrapT as
// OpenGL's. No sampler: LINEAR and REPEAT, the specification's defaults.
void read_sampler(Loader& loader, int index, const std::string& place, Texture& out) {
  if (index < 0) return;
  if (size_t(index) >= loader.model.samplers.size())
    loader.fail(place, "sampler " + std::to_string(index) + " out of range (" +
                           std::to_string(loader.model.samplers.size()) + " samplers)");
  const tinygltf::Sampler& sampler = loader.model.samplers[size_t(index)];
  if (sampler.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST) out.filter = TextureFilter::nearest;
  const std::string sampler_place = "samplers[" + std::to_string(index) + "]";
  auto wrap = [&](int mode, const char* key) {
    switch (mode) {
      case TINYGLTF_TEXTURE_WRAP_REPEAT:
        return TextureWrap::repeat;
      case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE:
        return TextureWrap::clamp;
      case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT:
        return TextureWrap::mirror;
      default:
        loader.fail(sampler_place + "." + key, "unknown wrap mode " + std::to_string(mode));
    }
    return TextureWrap::repeat;
  };
  out.wrap_u = wrap(sampler.wrapS, "wrapS");
  out.wrap_v = wrap(sampler.wrapT, "wrapT");
}

// `alpha`: the image's alpha channel alone, linear, one channel (-1 when it has none).
int scene_texture(Loader& loader, int texture_index, bool srgb, const std::string& place,
                  bool alpha = false) {
  const auto& model = loader.model;
  if (texture_index < 0 || size_t(texture_index) >= model.textures.size())
    loader.fail(place, "texture " + std::to_string(texture_index) + " out of range (" +
                           std::to_string(model.textures.size()) + " textures)");
  const tinygltf::Texture& texture = model.textures[size_t(texture_index)];
  const std::string texture_place = "textures[" + std::to_string(texture_index) + "]";
  for (const auto& [name, value] : texture.extensions)
    loader.warn_extension(texture_place + ".extensions." + name, name,
                          "unsupported texture extension ignored");
  const int image_index = texture.source;
  if (image_index < 0) {
    loader.warn(texture_place, "no source image; texture ignored");
    return -1;
  }
  if (size_t(image_index) >= model.images.size())
    loader.fail(texture_place + ".source", "image " + std::to_string(image_index) +
                                               " out of range (" +
                                               std::to_string(model.images.size()) + " images)");
  const auto key = std::make_tuple(image_index, texture.sampler, srgb, alpha);
  if (auto found = loader.texture_of_image.find(key); found != loader.texture_of_image.end())
    return found->second;

  const tinygltf::Image& image = model.images[size_t(image_index)];
  const std::string image_place = "images[" + std::to_string(image_index) + "]";
  int result = -1;
  const bool eight_bit =
      image.bits == 8 && image.pixel_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
  const bool sixteen_bit =
      image.bits == 16 && image.pixel_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
  const size_t expected = size_t(std::max(image.width, 0)) * size_t(std::max(image.height, 0)) *
                          size_t(std::max(image.component, 0)) * (sixteen_bit ? 2 : 1);
  if (image.width <= 0 || image.height <= 0 || image.component <= 0 || image.image.empty()) {
    if (!loader.image_failed[size_t(image_index)])
      loader.warn(image_place, "image '" + image.uri + "' was not loaded; texture ignored");
  } else if (!(eight_bit || sixteen_bit) || image.image.size() != expected) {
    loader.warn(image_place, "unsupported pixel layout (" + std::to_string(image.bits) +
                                 " bits); texture ignored");
  } else if (!alpha || image.component == 2 || image.component == 4) {
    Texture out;
    out.path = image.uri.empty() ? loader.path + "#" + image_place : image.uri;
    out.width = image.width;
    out.height = image.height;
    // Colour without alpha; alpha (MASK materials) as a texture of its own.
    out.channels = alpha ? 1 : std::min(image.component, 3);
    const int first = alpha ? image.component - 1 : 0;
    out.srgb_decoded = srgb;
    read_sampler(loader, texture.sampler, texture_place + ".sampler", out);
    out.texels.resize(size_t(out.width) * size_t(out.height) * size_t(out.channels));
    const double scale = sixteen_bit ? 65535.0 : 255.0;
    for (size_t p = 0; p < size_t(out.width) * size_t(out.height); ++p) {
      for (int c = 0; c < out.channels; ++c) {
        const size_t source = p * size_t(image.component) + size_t(first + c);
        double value;
        if (sixteen_bit) {
          uint16_t v;
          std::memcpy(&v, image.image.data() + 2 * source, 2);
          value = v / scale;
        } else {
          value = image.image[source] / scale;
        }
        out.texels[p * size_t(out.channels) + size_t(c)] =
            srgb ? srgb_eotf(float(value)) : float(value);
      }
    }
    result = int(loader.scene.textures.size());
    loader.scene.textures.push_back(std::move(out));
  }
  loader.texture_of_image[key] = result;
  return result;
}

// The UV set (`TEXCOORD_n`) and KHR_texture_transform of one textureInfo.
UvTransform texture_uv_transform(Loader& loader, const std::string& place, int tex_coord,
                                 const tinygltf::ExtensionMap& extensions) {
  UvTransform result;
  result.tex_coord = tex_coord;
  for (const auto& [name, value] : extensions) {
    const std::string ext_place = place + ".extensions." + name;
    if (name != "KHR_texture_transform") {
      loader.warn_extension(ext_place, name, "unsupported texture extension ignored");
      continue;
    }
    auto number = [&](const tinygltf::Value& v, const std::string& where) {
      if (!v.IsNumber() || !std::isfinite(v.GetNumberAsDouble()))
        loader.fail(where, "expected a finite number");
      return v.GetNumberAsDouble();
    };
    auto pair = [&](const char* key, glm::dvec2 fallback) {
      if (!value.Has(key)) return fallback;
      const tinygltf::Value& v = value.Get(key);
      if (!v.IsArray() || v.ArrayLen() != 2)
        loader.fail(ext_place + "." + key, "expected 2 numbers");
      return glm::dvec2(number(v.Get(0), ext_place + "." + key + "[0]"),
                        number(v.Get(1), ext_place + "." + key + "[1]"));
    };
    const glm::dvec2 offset = pair("offset", glm::dvec2(0.0));
    const glm::dvec2 scale = pair("scale", glm::dvec2(1.0));
    const double rotation =
        value.Has("rotation") ? number(value.Get("rotation"), ext_place + ".rotation") : 0.0;
    if (value.Has("texCoord")) {
      const tinygltf::Value& v = value.Get("texCoord");
      if (!v.IsInt() || v.GetNumberAsInt() < 0)
        loader.fail(ext_place + ".texCoord", "expected a non-negative integer");
      result.tex_coord = v.GetNumberAsInt();  // overrides the textureInfo's, per the extension
    }
    result.matrix = uv_transform_matrix(offset, rotation, scale);
  }
  return result;
}

// Material textures share the mesh's one `uvs` array: the first textured slot's UV set and
// transform win; a slot that differs is warned about.
void use_uv_transform(Loader& loader, std::optional<UvTransform>& chosen, const UvTransform& uv,
                      const std::string& place, const std::string& chosen_place) {
  if (!chosen)
    chosen = uv;
  else if (!(*chosen == uv))
    loader.warn(place, "UV set or KHR_texture_transform differs from " + chosen_place +
                           "'s; a mesh has one UV set, so that one is used");
}

// ---------------------------------------------------------------------------------------------
// Materials

double extension_number(const tinygltf::ExtensionMap& extensions, const std::string& extension,
                        const std::string& key, double fallback) {
  auto found = extensions.find(extension);
  if (found == extensions.end() || !found->second.Has(key)) return fallback;
  const tinygltf::Value& value = found->second.Get(key);
  return value.IsNumber() ? value.GetNumberAsDouble() : fallback;
}

// KHR_materials_specular that removes the dielectric specular layer: specularFactor 0 or a black
// specularColorFactor (either multiplies its texture). The base colour is then pure Lambert,
// which is what a lightbake diffuse material is. Blender's exporter writes a black
// specularColorFactor for a Principled BSDF with Specular 0 (docs/gltf.md).
bool removes_specular_layer(const tinygltf::Value& extension) {
  auto number = [&](const char* key, double fallback) {
    if (!extension.Has(key)) return fallback;
    const tinygltf::Value& value = extension.Get(key);
    return value.IsNumber() ? value.GetNumberAsDouble() : fallback;
  };
  if (number("specularFactor", 1.0) == 0.0) return true;
  if (!extension.Has("specularColorFactor")) return false;
  const tinygltf::Value& colour = extension.Get("specularColorFactor");
  if (!colour.IsArray() || colour.ArrayLen() != 3) return false;
  for (size_t c = 0; c < 3; ++c)
    if (!colour.Get(int(c)).IsNumber() || colour.Get(int(c)).GetNumberAsDouble() != 0.0)
      return false;
  return true;
}

vec3 factor3(const Loader& loader, const std::vector<double>& factor, const std::string& place,
             vec3 fallback) {
  if (factor.empty()) return fallback;
  if (factor.size() < 3) loader.fail(place, "expected 3 or 4 numbers");
  return vec3(float(factor[0]), float(factor[1]), float(factor[2]));
}

// extras.lightbake_group (bake/light_groups.h; Blender writes custom properties as extras):
// the light group named there, "" where there is none. Not a non-empty string without ','
// or '=': an error naming the place.
std::string light_group_extra(const Loader& loader, const tinygltf::Value& extras,
                              const std::string& place) {
  if (!extras.IsObject() || !extras.Has("lightbake_group")) return {};
  const tinygltf::Value& value = extras.Get("lightbake_group");
  const std::string name = value.IsString() ? value.Get<std::string>() : std::string();
  if (name.empty() || name.find_first_of(",=") != std::string::npos)
    loader.fail(place + ".extras.lightbake_group",
                "a light group's name must be a non-empty string without ',' or '='");
  return name;
}

Material convert_material(Loader& loader, int index, UvTransform& uv_transform) {
  const tinygltf::Material& source = loader.model.materials[size_t(index)];
  std::optional<UvTransform> uv;
  std::string uv_place;
  const std::string place = "materials[" + std::to_string(index) + "]";
  const auto& pbr = source.pbrMetallicRoughness;
  Material material;
  material.name = source.name.empty() ? "material" + std::to_string(index) : source.name;

  const vec3 base_color = factor3(loader, pbr.baseColorFactor,
                                  place + ".pbrMetallicRoughness.baseColorFactor", vec3(1.0f));
  const double metallic = pbr.metallicFactor;
  const double roughness = pbr.roughnessFactor;
  const double transmission =
      extension_number(source.extensions, "KHR_materials_transmission", "transmissionFactor", 0.0);
  const double ior = extension_number(source.extensions, "KHR_materials_ior", "ior", 1.5);

  material.reflectance = base_color;
  if (transmission > kTransmissionThreshold) {
    material.kind = MaterialKind::glass;
    material.ior = float(ior);
    if (roughness >= kMirrorRoughness)
      loader.warn(place + ".pbrMetallicRoughness.roughnessFactor",
                  "rough glass (roughness " + std::to_string(roughness) + ") treated as smooth");
  } else if (metallic >= kMetallicThreshold) {
    material.kind = roughness < kMirrorRoughness ? MaterialKind::mirror : MaterialKind::glossy;
    if (material.kind == MaterialKind::glossy) material.roughness = float(roughness);
  } else {
    material.kind = MaterialKind::diffuse;
  }
  if (metallic > 0.05 && metallic < 0.95)
    loader.warn(place + ".pbrMetallicRoughness.metallicFactor",
                "partly metallic (" + std::to_string(metallic) + ") treated as " +
                    (metallic >= kMetallicThreshold ? "metal" : "dielectric"));
  if (transmission > 0.0 && transmission <= kTransmissionThreshold)
    loader.warn(place + ".extensions.KHR_materials_transmission",
                "transmission " + std::to_string(transmission) + " <= 0.5 treated as opaque");

  // Emission: radiance [W/(sr m^2)] = emissiveFactor * emissiveStrength (docs/gltf.md).
  const vec3 emissive =
      factor3(loader, source.emissiveFactor, place + ".emissiveFactor", vec3(0.0f));
  const double strength = extension_number(source.extensions, "KHR_materials_emissive_strength",
                                           "emissiveStrength", 1.0);
  material.emission = emissive * float(strength);
  material.two_sided_emission = source.doubleSided && material.is_emitter();
  material.light_group = light_group_extra(loader, source.extras, place);
  material.two_sided_reflection = source.doubleSided && material.is_diffuse();
  if (source.emissiveTexture.index >= 0)
    loader.warn(place + ".emissiveTexture", "ignored; emission is emissiveFactor x strength");

  if (pbr.baseColorTexture.index >= 0) {
    const std::string tex_place = place + ".pbrMetallicRoughness.baseColorTexture";
    if (material.kind == MaterialKind::diffuse) {
      material.reflectance_texture =
          scene_texture(loader, pbr.baseColorTexture.index, true, tex_place);
      if (material.reflectance_texture >= 0) {
        use_uv_transform(loader, uv,
                         texture_uv_transform(loader, tex_place, pbr.baseColorTexture.texCoord,
                                              pbr.baseColorTexture.extensions),
                         tex_place, uv_place);
        uv_place = "baseColorTexture";
      }
    } else {
      loader.warn(tex_place, std::string("ignored on a ") + to_string(material.kind) +
                                 " material (only diffuse reflectance is textured)");
    }
  }
  if (pbr.metallicRoughnessTexture.index >= 0)
    loader.warn(place + ".pbrMetallicRoughness.metallicRoughnessTexture",
                "ignored; the factors choose the material");
  if (source.occlusionTexture.index >= 0)
    loader.warn(place + ".occlusionTexture", "ignored; the bake computes occlusion");
  if (source.normalTexture.index >= 0) {
    const std::string tex_place = place + ".normalTexture";
    if (material.kind == MaterialKind::diffuse) {
      const int texture = scene_texture(loader, source.normalTexture.index, false, tex_place);
      if (texture >= 0) {
        use_uv_transform(loader, uv,
                         texture_uv_transform(loader, tex_place, source.normalTexture.texCoord,
                                              source.normalTexture.extensions),
                         tex_place, uv_place);
        material.bump = BumpKind::normal_map;
        material.bump_texture = texture;
        material.bump_scale = float(source.normalTexture.scale);
      }
    } else {
      loader.warn(tex_place, std::string("ignored on a ") + to_string(material.kind) +
                                 " material (bump applies to diffuse surfaces)");
    }
  }
  if (source.alphaMode == "MASK" || source.alphaMode == "BLEND") {
    // alpha = baseColorFactor.a x baseColorTexture.a; MASK cuts where it is below alphaCutoff,
    // BLEND lets 1 - alpha of the light through (accel.cpp).
    material.alpha_cutoff = float(source.alphaCutoff);
    material.alpha_factor = pbr.baseColorFactor.size() >= 4 ? float(pbr.baseColorFactor[3]) : 1.0f;
    if (pbr.baseColorTexture.index >= 0)
      material.alpha_texture = scene_texture(loader, pbr.baseColorTexture.index, false,
                                             place + ".pbrMetallicRoughness.baseColorTexture",
                                             true);
    const bool has_alpha = material.alpha_texture >= 0;
    if (source.alphaMode == "MASK")
      material.alpha_mask = has_alpha || material.alpha_factor < material.alpha_cutoff;
    else
      material.alpha_blend = has_alpha || material.alpha_factor < 1.0f;
  } else if (source.alphaMode != "OPAQUE") {
    loader.warn(place + ".alphaMode", source.alphaMode + " treated as OPAQUE");
  }
  for (const auto& [name, value] : source.extensions) {
    if (kSupportedExtensions.count(name)) continue;
    if (loader.lightbake_export && (name == "MOZ_lightmap" || name == kDirectionalExtension))
      continue;
    // No specular layer on a diffuse material: exactly what lightbake renders, no warning.
    if (name == "KHR_materials_specular" && material.kind == MaterialKind::diffuse &&
        removes_specular_layer(value))
      continue;
    if (name == "KHR_materials_unlit")
      loader.warn_extension(place + ".extensions." + name, name, "unlit treated as diffuse");
    else
      loader.warn_extension(place + ".extensions." + name, name,
                            "unsupported material extension ignored");
  }
  uv_transform = uv.value_or(UvTransform{});
  return material;
}

int material_for_primitive(Loader& loader, int material, const std::string& place) {
  if (material >= 0) {
    if (size_t(material) >= loader.model.materials.size())
      loader.fail(place + ".material", "material " + std::to_string(material) + " out of range (" +
                                           std::to_string(loader.model.materials.size()) +
                                           " materials)");
    return material;
  }
  if (loader.default_material < 0) {
    // glTF's default material is a rough white metal; a baker wants a plain diffuse surface.
    Material fallback;
    fallback.name = "gltf_default";
    fallback.reflectance = vec3(0.8f);
    loader.default_material = int(loader.scene.materials.size());
    loader.scene.materials.push_back(fallback);
  }
  return loader.default_material;
}

// ---------------------------------------------------------------------------------------------
// Primitives: read once in the mesh's local space, instanced per node.

struct LocalPrimitive {
  bool usable = false;
  std::string name;
  int material = 0;
  std::vector<vec3> positions, normals;
  std::vector<vec2> uvs, lightmap_uvs;
  std::vector<vec4> tangents;
  std::vector<uvec3> triangles;
};

template <typename Vec>
std::vector<Vec> to_vectors(const AccessorValues& values) {
  std::vector<Vec> out(values.count);
  for (size_t i = 0; i < values.count; ++i)
    for (int c = 0; c < Vec::length() && c < values.components; ++c)
      out[i][c] = float(values.at(i, c));
  return out;
}

LocalPrimitive read_primitive(Loader& loader, int mesh_index, int primitive_index) {
  const tinygltf::Mesh& mesh = loader.model.meshes[size_t(mesh_index)];
  const tinygltf::Primitive& primitive = mesh.primitives[size_t(primitive_index)];
  const std::string place = "meshes[" + std::to_string(mesh_index) + "].primitives[" +
                            std::to_string(primitive_index) + "]";
  LocalPrimitive out;
  out.name = mesh.name.empty() ? "mesh" + std::to_string(mesh_index) : mesh.name;
  if (mesh.primitives.size() > 1) out.name += "." + std::to_string(primitive_index);

  const int mode = primitive.mode < 0 ? TINYGLTF_MODE_TRIANGLES : primitive.mode;
  if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
      mode != TINYGLTF_MODE_TRIANGLE_FAN) {
    loader.warn(place + ".mode", "mode " + std::to_string(mode) +
                                     " (points or lines) has no area; primitive skipped");
    return out;
  }
  if (!primitive.targets.empty()) loader.morph_targets.note(place + ".targets");

  const auto& attributes = primitive.attributes;
  auto position = attributes.find("POSITION");
  if (position == attributes.end()) {
    loader.warn(place + ".attributes", "no POSITION; primitive skipped");
    return out;
  }
  const std::string attribute_place = place + ".attributes.";
  const AccessorValues positions =
      read_accessor(loader, position->second, attribute_place + "POSITION", {TINYGLTF_TYPE_VEC3});
  out.positions = to_vectors<vec3>(positions);
  const size_t vertex_count = out.positions.size();

  auto read_optional = [&](const char* name, int type, auto& target) {
    auto found = attributes.find(name);
    if (found == attributes.end()) return;
    const AccessorValues values =
        read_accessor(loader, found->second, attribute_place + name, {type});
    if (values.count != vertex_count)
      loader.fail(attribute_place + name, std::to_string(values.count) +
                                              " elements, but POSITION has " +
                                              std::to_string(vertex_count));
    target = to_vectors<typename std::decay_t<decltype(target)>::value_type>(values);
  };
  read_optional("NORMAL", TINYGLTF_TYPE_VEC3, out.normals);
  // Textures are sampled with the material's UV set, transformed by its KHR_texture_transform.
  out.material = material_for_primitive(loader, primitive.material, place);
  const UvTransform uv_transform = size_t(out.material) < loader.material_uvs.size()
                                       ? loader.material_uvs[size_t(out.material)]
                                       : UvTransform{};
  const std::string uv_set = "TEXCOORD_" + std::to_string(uv_transform.tex_coord);
  read_optional(uv_set.c_str(), TINYGLTF_TYPE_VEC2, out.uvs);
  for (vec2& uv : out.uvs) uv = apply_uv_transform(uv_transform.matrix, uv);
  read_optional("TEXCOORD_1", TINYGLTF_TYPE_VEC2, out.lightmap_uvs);
  read_optional("TANGENT", TINYGLTF_TYPE_VEC4, out.tangents);
  for (const auto& [name, accessor] : attributes) {
    if (name == "POSITION" || name == "NORMAL" || name == "TEXCOORD_0" || name == "TEXCOORD_1" ||
        name == "TANGENT" || name == uv_set)
      continue;
    if (name.rfind("JOINTS_", 0) == 0 || name.rfind("WEIGHTS_", 0) == 0) continue;  // skins
    if (loader.lightbake_export && name == "COLOR_0") continue;  // older exports' radiosity
    loader.warn(attribute_place + name, "attribute ignored");
  }

  // Vertex order: the index buffer, or 0..n-1.
  std::vector<uint32_t> order;
  if (primitive.indices >= 0) {
    const AccessorValues indices =
        read_accessor(loader, primitive.indices, place + ".indices", {TINYGLTF_TYPE_SCALAR});
    const int type = loader.model.accessors[size_t(primitive.indices)].componentType;
    if (type == TINYGLTF_COMPONENT_TYPE_FLOAT || type == TINYGLTF_COMPONENT_TYPE_BYTE ||
        type == TINYGLTF_COMPONENT_TYPE_SHORT || type == TINYGLTF_COMPONENT_TYPE_INT)
      loader.fail(place + ".indices",
                  "indices must be unsigned integers (componentType " + std::to_string(type) + ")");
    order.resize(indices.count);
    for (size_t i = 0; i < indices.count; ++i) {
      const double index = indices.values[i];
      if (index >= double(vertex_count))
        loader.fail(place + ".indices", "index " + std::to_string(uint64_t(index)) +
                                            " at position " + std::to_string(i) +
                                            " out of range (" + std::to_string(vertex_count) +
                                            " vertices)");
      order[i] = uint32_t(index);
    }
  } else {
    order.resize(vertex_count);
    for (size_t i = 0; i < vertex_count; ++i) order[i] = uint32_t(i);
  }

  if (mode == TINYGLTF_MODE_TRIANGLES) {
    if (order.size() % 3 != 0)
      loader.warn(place, std::to_string(order.size()) +
                             " vertices is not a multiple of 3; the last " +
                             std::to_string(order.size() % 3) + " ignored");
    for (size_t i = 0; i + 2 < order.size(); i += 3)
      out.triangles.push_back({order[i], order[i + 1], order[i + 2]});
  } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
    for (size_t i = 0; i + 2 < order.size(); ++i)
      out.triangles.push_back(i % 2 == 0 ? uvec3(order[i], order[i + 1], order[i + 2])
                                         : uvec3(order[i + 1], order[i], order[i + 2]));
  } else {  // fan
    for (size_t i = 1; i + 1 < order.size(); ++i)
      out.triangles.push_back({order[0], order[i], order[i + 1]});
  }
  out.usable = !out.triangles.empty();
  if (!out.usable) loader.warn(place, "no triangles; primitive skipped");
  return out;
}

Mesh instance_primitive(const LocalPrimitive& local, const dmat4& world, const std::string& name) {
  Mesh mesh;
  mesh.name = name;
  mesh.material = local.material;
  const mat4 m(world);
  const mat3 linear(m);
  const mat3 normal_matrix = glm::inverseTranspose(linear);
  const bool mirrored = glm::determinant(linear) < 0.0f;

  mesh.positions.reserve(local.positions.size());
  for (vec3 p : local.positions) mesh.positions.push_back(vec3(m * vec4(p, 1.0f)));
  for (vec3 n : local.normals) {
    const vec3 world_normal = normal_matrix * n;
    const float length = glm::length(world_normal);
    mesh.normals.push_back(length > 0.0f ? world_normal / length : world_normal);
  }
  for (vec4 t : local.tangents) {
    vec3 world_tangent = linear * vec3(t);
    const float length = glm::length(world_tangent);
    if (length > 0.0f) world_tangent /= length;
    mesh.tangents.push_back(vec4(world_tangent, mirrored ? -t.w : t.w));
  }
  mesh.uvs = local.uvs;
  mesh.lightmap_uvs = local.lightmap_uvs;
  mesh.triangles = local.triangles;
  // A mirroring transform turns counter-clockwise into clockwise; keep the front the front.
  if (mirrored)
    for (uvec3& t : mesh.triangles) std::swap(t.y, t.z);
  return mesh;
}

// ---------------------------------------------------------------------------------------------
// Nodes

// `node_index` names the place in messages; the string is built only on failure, since a walk
// may visit a million nodes.
dmat4 local_transform(const Loader& loader, const tinygltf::Node& node, int node_index) {
  auto place = [&] { return "nodes[" + std::to_string(node_index) + "]"; };
  if (!node.matrix.empty()) {
    if (node.matrix.size() != 16) loader.fail(place() + ".matrix", "expected 16 numbers");
    dmat4 m;
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) m[c][r] = node.matrix[size_t(c * 4 + r)];  // column-major
    return m;
  }
  dmat4 t(1.0), r(1.0), s(1.0);
  if (!node.translation.empty()) {
    if (node.translation.size() != 3) loader.fail(place() + ".translation", "expected 3 numbers");
    t = glm::translate(dmat4(1.0),
                       glm::dvec3(node.translation[0], node.translation[1], node.translation[2]));
  }
  if (!node.rotation.empty()) {
    if (node.rotation.size() != 4)
      loader.fail(place() + ".rotation", "expected 4 numbers (x, y, z, w)");
    glm::dquat q(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);
    const double length = glm::length(q);
    if (!(length > 0.0)) loader.fail(place() + ".rotation", "zero or invalid quaternion");
    r = glm::mat4_cast(q / length);
  }
  if (!node.scale.empty()) {
    if (node.scale.size() != 3) loader.fail(place() + ".scale", "expected 3 numbers");
    s = glm::scale(dmat4(1.0), glm::dvec3(node.scale[0], node.scale[1], node.scale[2]));
  }
  return t * r * s;
}

float extras_number(const tinygltf::Value& extras, const char* key) {
  if (!extras.IsObject() || !extras.Has(key)) return 0.0f;
  const tinygltf::Value& value = extras.Get(key);
  return value.IsNumber() ? float(value.GetNumberAsDouble()) : 0.0f;
}

std::string extras_string(const tinygltf::Value& extras, const char* key) {
  if (!extras.IsObject() || !extras.Has(key)) return {};
  const tinygltf::Value& value = extras.Get(key);
  return value.IsString() ? value.Get<std::string>() : std::string();
}

// Triangles a mesh will yield, from its accessor counts alone (nothing is read).
uint64_t estimated_triangles(const tinygltf::Model& model, int mesh_index) {
  uint64_t triangles = 0;
  for (const tinygltf::Primitive& primitive : model.meshes[size_t(mesh_index)].primitives) {
    int accessor = primitive.indices;
    if (accessor < 0) {
      auto position = primitive.attributes.find("POSITION");
      accessor = position == primitive.attributes.end() ? -1 : position->second;
    }
    if (accessor < 0 || size_t(accessor) >= model.accessors.size()) continue;
    const uint64_t count = model.accessors[size_t(accessor)].count;
    const int mode = primitive.mode < 0 ? TINYGLTF_MODE_TRIANGLES : primitive.mode;
    triangles += mode == TINYGLTF_MODE_TRIANGLES ? count / 3 : (count > 2 ? count - 2 : 0);
  }
  return triangles;
}

uint64_t saturating_add(uint64_t a, uint64_t b) {
  return a > UINT64_MAX - b ? UINT64_MAX : a + b;
}

// What expanding a node's subtree would produce; a node DAG can reuse a subtree 2^30 times.
struct Expansion {
  uint64_t visits = 0, instances = 0, triangles = 0;
  void add(const Expansion& other) {
    visits = saturating_add(visits, other.visits);
    instances = saturating_add(instances, other.instances);
    triangles = saturating_add(triangles, other.triangles);
  }
};

// Counts the expansion of every node reachable from `roots` without expanding (depth-first
// with an explicit stack, so a 20,000-deep chain is no deeper on the call stack than one
// node), refuses cycles and out-of-range children, then refuses roots past the limits of
// input_limits.h before any mesh is copied.
void check_expansion(const Loader& loader, const std::vector<std::pair<int, std::string>>& roots) {
  const auto& model = loader.model;
  const size_t n = model.nodes.size();
  enum : char { unseen, open, done };
  std::vector<char> state(n, unseen);
  std::vector<Expansion> expansion(n);
  auto check_index = [&](int node, const std::string& from) {
    if (node < 0 || size_t(node) >= n)
      loader.fail(
          from, "node " + std::to_string(node) + " out of range (" + std::to_string(n) + " nodes)");
  };
  Expansion total;
  for (const auto& [root, root_place] : roots) {
    check_index(root, root_place);
    struct Frame {
      int node;
      size_t next_child;
    };
    std::vector<Frame> stack;
    if (state[size_t(root)] == unseen) {
      stack.push_back({root, 0});
      state[size_t(root)] = open;
    }
    while (!stack.empty()) {
      Frame& frame = stack.back();
      const tinygltf::Node& node = model.nodes[size_t(frame.node)];
      if (frame.next_child < node.children.size()) {
        const size_t c = frame.next_child++;
        const int child = node.children[c];
        const std::string from =
            "nodes[" + std::to_string(frame.node) + "].children[" + std::to_string(c) + "]";
        check_index(child, from);
        if (state[size_t(child)] == open)
          loader.fail(from,
                      "node hierarchy has a cycle through nodes[" + std::to_string(child) + "]");
        if (state[size_t(child)] == unseen) {
          state[size_t(child)] = open;
          stack.push_back({child, 0});
        }
        continue;
      }
      Expansion& e = expansion[size_t(frame.node)];
      e.visits = 1;
      if (node.mesh >= 0 && size_t(node.mesh) < model.meshes.size()) {
        e.instances = 1;
        e.triangles = estimated_triangles(model, node.mesh);
      }
      for (int child : node.children) e.add(expansion[size_t(child)]);
      state[size_t(frame.node)] = done;
      stack.pop_back();
    }
    total.add(expansion[size_t(root)]);
    const std::string where = root_place + " (nodes[" + std::to_string(root) + "])";
    auto refuse = [&](const char* what, uint64_t count, uint64_t limit) {
      if (count > limit)
        loader.fail(where,
                    "the hierarchy expands to " +
                        (count == UINT64_MAX ? std::string("over 2^64") : std::to_string(count)) +
                        " " + what + " (limit " + std::to_string(limit) +
                        ", bake/io/input_limits.h)");
    };
    refuse("mesh instances", total.instances, limits::kMaxInstances);
    refuse("triangles", total.triangles, limits::kMaxTriangles);
    refuse("node visits", total.visits, limits::kMaxNodeVisits);
  }
}

struct NodeWalker {
  Loader& loader;
  std::vector<std::vector<LocalPrimitive>> primitives;  // per glTF mesh, read on first use
  std::vector<bool> read;

  explicit NodeWalker(Loader& l)
      : loader(l), primitives(l.model.meshes.size()), read(l.model.meshes.size(), false) {}

  // Places every mesh and camera under the roots, in depth-first order. check_expansion has
  // bounded the work and ruled out cycles and bad indices.
  void walk(const std::vector<std::pair<int, std::string>>& roots) {
    check_expansion(loader, roots);
    struct Pending {
      int node;
      dmat4 parent;
    };
    std::vector<Pending> stack;
    for (const auto& root : roots) {
      stack.push_back({root.first, dmat4(1.0)});
      while (!stack.empty()) {
        const Pending pending = stack.back();
        stack.pop_back();
        const tinygltf::Node& node = loader.model.nodes[size_t(pending.node)];
        const dmat4 world = visit(pending.node, pending.parent);
        for (size_t c = node.children.size(); c-- > 0;) stack.push_back({node.children[c], world});
      }
    }
  }

  dmat4 visit(int node_index, const dmat4& parent) {
    const tinygltf::Node& node = loader.model.nodes[size_t(node_index)];
    const dmat4 world = parent * local_transform(loader, node, node_index);
    if (node.mesh < 0 && node.camera < 0 && node.skin < 0 && node.extensions.empty()) return world;
    const std::string place = "nodes[" + std::to_string(node_index) + "]";
    if (node.mesh >= 0) add_mesh_instance(node, node_index, world, place);
    if (node.camera >= 0) add_camera(node, world, place);
    if (node.skin >= 0) loader.skins.note(place + ".skin");
    for (const auto& [name, value] : node.extensions) {
      if (name == "KHR_lights_punctual")
        add_lamp(value, world, place + ".extensions." + name,
                 light_group_extra(loader, node.extras, place));
      else
        loader.warn_extension(place + ".extensions." + name, name,
                              "unsupported node extension ignored");
    }
    return world;
  }

  void add_mesh_instance(const tinygltf::Node& node, int node_index, const dmat4& world,
                         const std::string& place) {
    const auto& model = loader.model;
    if (size_t(node.mesh) >= model.meshes.size())
      loader.fail(place + ".mesh", "mesh " + std::to_string(node.mesh) + " out of range (" +
                                       std::to_string(model.meshes.size()) + " meshes)");
    const size_t mesh_index = size_t(node.mesh);
    if (!read[mesh_index]) {
      for (size_t p = 0; p < model.meshes[mesh_index].primitives.size(); ++p)
        primitives[mesh_index].push_back(read_primitive(loader, int(mesh_index), int(p)));
      read[mesh_index] = true;
    }
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r)
        if (!std::isfinite(world[c][r])) loader.fail(place, "transform is not finite");
    MeshBakeSettings bake;
    bool dynamic = false;  // a moving object, lit by the light probes (Mesh::dynamic)
    std::vector<vec3> probe_sh;  // its light as a lightbake export wrote it (Mesh::probe_sh)
    // Blender exports custom properties as extras: the node's win over the mesh's.
    for (const tinygltf::Value* extras : {&model.meshes[mesh_index].extras, &node.extras}) {
      if (extras->IsObject() && extras->Has("dynamic")) {
        const tinygltf::Value& value = extras->Get("dynamic");
        // Blender writes a boolean custom property as 0 or 1.
        if (value.IsBool())
          dynamic = value.Get<bool>();
        else if (value.IsNumber())
          dynamic = value.GetNumberAsDouble() != 0.0;
        else
          loader.fail(place, "extras.dynamic must be true or false");
      }
      if (extras->IsObject() && extras->Has("lightbake_probe_sh")) {
        const tinygltf::Value& sh = extras->Get("lightbake_probe_sh");
        if (!sh.IsArray() || sh.ArrayLen() != 27)
          loader.fail(place, "extras.lightbake_probe_sh must hold 27 numbers");
        probe_sh.assign(9, vec3(0.0f));
        for (int k = 0; k < 27; ++k) {
          const tinygltf::Value& v = sh.Get(k);
          if (!v.IsNumber() || !std::isfinite(v.GetNumberAsDouble()))
            loader.fail(place, "extras.lightbake_probe_sh must hold 27 finite numbers");
          probe_sh[size_t(k / 3)][k % 3] = float(v.GetNumberAsDouble());
        }
      }
      if (float v = extras_number(*extras, "lightbake_texel_size"); v > 0) bake.texel_size = v;
      if (float v = extras_number(*extras, "lightbake_patch_size"); v > 0) bake.patch_size = v;
      const std::string origins = extras_string(*extras, "lightbake_caustic_origins");
      if (origins == "centre" || origins == "center")
        bake.caustic_origins = CausticOrigins::centre;
      else if (origins == "area")
        bake.caustic_origins = CausticOrigins::over_light;
      else if (!origins.empty())
        loader.fail(
            place, "extras.lightbake_caustic_origins is 'centre' or 'area', not '" + origins + "'");
    }
    const std::string base = node.name.empty() ? "node" + std::to_string(node_index) : node.name;
    for (const LocalPrimitive& local : primitives[mesh_index]) {
      if (!local.usable) continue;
      const std::string name = primitives[mesh_index].size() > 1 ? base + "/" + local.name : base;
      Mesh mesh = instance_primitive(local, world, name);
      mesh.bake = bake;
      mesh.dynamic = dynamic;
      mesh.probe_sh = probe_sh;
      loader.scene.meshes.push_back(std::move(mesh));
    }
  }

  // A KHR_lights_punctual lamp at the node: at its origin, shining down its local -Z. glTF's
  // photometric units become radiometric at 683 lm/W (docs/gltf.md).
  void add_lamp(const tinygltf::Value& extension, const dmat4& world, const std::string& place,
                const std::string& group) {
    const auto& lights = loader.model.lights;
    const tinygltf::Value& index_value = extension.Get("light");
    if (!index_value.IsNumber() && !index_value.IsInt())
      loader.fail(place + ".light", "must be a light index");
    const double index = index_value.GetNumberAsDouble();
    if (!(index >= 0.0 && index < double(lights.size())) || index != std::floor(index))
      loader.fail(place + ".light", "light " + std::to_string(index) + " out of range (" +
                                        std::to_string(lights.size()) + " lights)");
    const tinygltf::Light& source = lights[size_t(index)];
    const std::string light_place =
        "extensions.KHR_lights_punctual.lights[" + std::to_string(size_t(index)) + "]";
    Lamp lamp;
    lamp.name = source.name.empty() ? "light" + std::to_string(size_t(index)) : source.name;
    if (source.type == "point")
      lamp.kind = LampKind::point;
    else if (source.type == "spot")
      lamp.kind = LampKind::spot;
    else if (source.type == "directional")
      lamp.kind = LampKind::directional;
    else {
      loader.warn(light_place + ".type", "unknown light type '" + source.type + "'; skipped");
      return;
    }
    const vec3 colour = factor3(loader, source.color, light_place + ".color", vec3(1.0f));
    if (!std::isfinite(colour.x + colour.y + colour.z) ||
        glm::any(glm::lessThan(colour, vec3(0.0f))))
      loader.fail(light_place + ".color", "must be finite and not negative");
    if (!(source.intensity >= 0.0) || !std::isfinite(source.intensity))
      loader.fail(light_place + ".intensity", "must be finite and not negative");
    // candela -> W/sr, lux -> W/m^2.
    lamp.intensity = colour * float(source.intensity / kLumensPerWatt);
    if (!(source.range >= 0.0) || !std::isfinite(source.range))
      loader.fail(light_place + ".range", "must be positive");
    lamp.range = float(source.range);
    if (lamp.kind == LampKind::spot) {
      const double inner = source.spot.innerConeAngle, outer = source.spot.outerConeAngle;
      // inner == outer is outside the extension's rule (inner < outer) but what Blender's
      // exporter writes for a spot with blend 0: a hard-edged cone (spot_falloff's floor).
      if (!(inner >= 0.0 && inner <= outer && outer > 0.0 && outer <= glm::half_pi<double>()))
        loader.fail(light_place + ".spot",
                    "cone angles need 0 <= innerConeAngle <= "
                    "outerConeAngle <= pi/2, got " +
                        std::to_string(inner) + " and " + std::to_string(outer));
      lamp.inner_cone = float(inner);
      lamp.outer_cone = float(outer);
    }
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r)
        if (!std::isfinite(world[c][r])) loader.fail(place, "transform is not finite");
    lamp.position = vec3(world * glm::dvec4(0.0, 0.0, 0.0, 1.0));
    const glm::dvec3 direction = glm::dmat3(world) * glm::dvec3(0.0, 0.0, -1.0);
    if (!(glm::length(direction) > 0.0))
      loader.fail(place, "transform collapses the light's direction");
    lamp.direction = vec3(glm::normalize(direction));
    lamp.light_group = group;
    loader.scene.lights.push_back(std::move(lamp));
  }

  void add_camera(const tinygltf::Node& node, const dmat4& world, const std::string& place) {
    const auto& model = loader.model;
    if (size_t(node.camera) >= model.cameras.size())
      loader.fail(place + ".camera", "camera " + std::to_string(node.camera) + " out of range (" +
                                         std::to_string(model.cameras.size()) + " cameras)");
    const tinygltf::Camera& source = model.cameras[size_t(node.camera)];
    const std::string camera_place = "cameras[" + std::to_string(node.camera) + "]";
    if (source.type != "perspective") {
      loader.warn(camera_place, "'" + source.type + "' camera not supported; skipped");
      return;
    }
    const double yfov = source.perspective.yfov;
    if (!(yfov > 0.0 && yfov < glm::pi<double>()))
      loader.fail(camera_place + ".perspective.yfov",
                  "must be in (0, pi) radians, got " + std::to_string(yfov));
    Camera camera;
    camera.name = !node.name.empty()     ? node.name
                  : !source.name.empty() ? source.name
                                         : camera_place;
    // glTF cameras look down their local -Z with +Y up.
    const glm::dvec3 position(world * glm::dvec4(0, 0, 0, 1));
    const glm::dvec3 forward = glm::normalize(glm::dvec3(world * glm::dvec4(0, 0, -1, 0)));
    const glm::dvec3 up = glm::normalize(glm::dvec3(world * glm::dvec4(0, 1, 0, 0)));
    camera.position = vec3(position);
    camera.target = vec3(position + forward);
    camera.up = vec3(up);
    camera.vertical_fov_deg = float(glm::degrees(yfov));
    // What `lightbake export` records beside the view (docs/export.md), so a re-imported
    // camera renders as the scene's did.
    auto extra = [&](const char* key, float& out, float lo) {
      const tinygltf::Value& v = source.extras.Get(key);
      if (v.IsNumber() && std::isfinite(v.GetNumberAsDouble()) && v.GetNumberAsDouble() >= lo)
        out = float(v.GetNumberAsDouble());
    };
    extra("lightbake_aperture_radius_m", camera.aperture_radius, 0.0f);
    extra("lightbake_focus_distance_m", camera.focus_distance, 0.0f);
    extra("lightbake_exposure_stops", camera.exposure, -1e3f);
    loader.scene.cameras.push_back(camera);
  }
};

// ---------------------------------------------------------------------------------------------
// File level

bool has_glb_magic(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char magic[4] = {};
  in.read(magic, 4);
  return in.gcount() == 4 && std::memcmp(magic, "glTF", 4) == 0;
}

// tinygltf says only "Invalid glTF binary" for a damaged .glb; say where it is damaged.
void check_glb_layout(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)),
                                   std::istreambuf_iterator<char>());
  auto u32 = [&](size_t offset) {
    uint32_t v;
    std::memcpy(&v, bytes.data() + offset, 4);
    return v;
  };
  const size_t size = bytes.size();
  if (size < 12)
    throw SceneError(path + ": at byte 0: truncated .glb header (" + std::to_string(size) +
                     " bytes)");
  if (u32(4) != 2)
    throw SceneError(path + ": at byte 4: .glb version " + std::to_string(u32(4)) +
                     " (expected 2)");
  if (u32(8) > size)
    throw SceneError(path + ": at byte " + std::to_string(size) + ": truncated .glb: the header " +
                     "declares " + std::to_string(u32(8)) + " bytes, the file has " +
                     std::to_string(size));
  size_t offset = 12;
  for (int chunk = 0; offset < size_t(u32(8)); ++chunk) {
    const std::string place =
        path + ": at byte " + std::to_string(offset) + " (chunk " + std::to_string(chunk) + "): ";
    if (offset + 8 > size) throw SceneError(place + "truncated chunk header");
    const size_t length = u32(offset);
    if (length > size - offset - 8)
      throw SceneError(place + "chunk of " + std::to_string(length) + " bytes runs past the end");
    offset += 8 + length;
  }
}

void check_extensions(Loader& loader) {
  const auto& model = loader.model;
  for (size_t i = 0; i < model.extensionsRequired.size(); ++i) {
    const std::string& name = model.extensionsRequired[i];
    if (kSupportedExtensions.count(name)) continue;
    const std::string place = "extensionsRequired[" + std::to_string(i) + "]";
    if (kIgnorableExtensions.count(name))
      loader.warn(place, "required extension " + name + " is not supported; ignored");
    else
      loader.fail(place, "required extension " + name +
                             " is not supported (the data cannot be read without it)");
  }
}

// One warning each for what was skipped element by element, and for extensions used where the
// loader does not look (the JSON precheck lists them all).
void warn_skipped(Loader& loader, const GltfJsonSummary& summary) {
  const auto& used = loader.model.extensionsUsed;
  if (summary.animations > 0)
    loader.warn("animations", std::to_string(summary.animations) +
                                  " animation(s) ignored; the scene is loaded at rest" +
                                  (std::count(used.begin(), used.end(), "KHR_animation_pointer")
                                       ? " (KHR_animation_pointer included)"
                                       : ""));
  if (loader.skins.count > 0)
    loader.warn(loader.skins.first_place, "skins on " + std::to_string(loader.skins.count) +
                                              " node(s) ignored; bind pose used");
  if (loader.morph_targets.count > 0)
    loader.warn(loader.morph_targets.first_place, "morph targets on " +
                                                      std::to_string(loader.morph_targets.count) +
                                                      " primitive(s) ignored; base shape used");
  for (const auto& [name, place] : summary.extensions) {
    if (kSupportedExtensions.count(name)) continue;
    if (loader.lightbake_export && (name == "MOZ_lightmap" || name == kDirectionalExtension))
      continue;  // read by read_gltf_bake
    if (name == "LIGHTBAKE_light_probes") continue;  // ours: read into Scene::probe_grid
    if (name == "KHR_materials_specular") continue;  // convert_material warns where it matters
    loader.warn_extension(place, name, "unsupported extension ignored");
  }
}

// scene.extensions.LIGHTBAKE_light_probes (docs/light-probes.md, "In the exported file"): the
// grid an export wrote, in the frame of the scene's root node (`frame`, the export's
// `lightbake` node), placed in the scene's coordinates. A frame that turns or shears the grid
// cannot keep it axis-aligned: refused, as is any field out of shape.
ProbeGrid read_probe_grid(const Loader& loader, const tinygltf::Value& grid, const dmat4& frame,
                          const std::string& place) {
  if (!grid.IsObject()) loader.fail(place, "must be an object");
  auto numbers = [&](const char* name, size_t count) {
    const std::string at = place + "." + name;
    if (!grid.Has(name)) loader.fail(at, "missing");
    const tinygltf::Value& array = grid.Get(name);
    if (!array.IsArray() || array.ArrayLen() != count)
      loader.fail(at, "must hold " + std::to_string(count) + " numbers");
    std::vector<double> out(count);
    for (size_t i = 0; i < count; ++i) {
      const tinygltf::Value& v = array.Get(int(i));
      if (!v.IsNumber() || !std::isfinite(v.GetNumberAsDouble()))
        loader.fail(at + "[" + std::to_string(i) + "]", "must be a finite number");
      out[i] = v.GetNumberAsDouble();
    }
    return out;
  };
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      if ((r == c) != (frame[c][r] != 0.0) || (r == c && frame[c][r] < 0.0))
        loader.fail(place, "its frame (the scene's root node) must only move and scale, so "
                           "the grid stays aligned with the axes");
  const std::vector<double> origin = numbers("origin", 3), spacing = numbers("spacing", 3),
                            counts = numbers("counts", 3);
  ProbeGrid out;
  size_t size = 1;
  for (int a = 0; a < 3; ++a) {
    if (!(spacing[size_t(a)] > 0.0))
      loader.fail(place + ".spacing[" + std::to_string(a) + "]", "must be positive");
    const double n = counts[size_t(a)];
    if (n != std::floor(n) || n < 1.0 || n > 4096.0)
      loader.fail(place + ".counts[" + std::to_string(a) + "]", "must be a whole 1 .. 4096");
    size *= size_t(n);
    if (size > (size_t(1) << 24))
      loader.fail(place + ".counts", "more than 2^24 probes");
    out.counts[a] = int(n);
    out.origin[a] = float(frame[3][a] + frame[a][a] * origin[size_t(a)]);
    out.spacing[a] = float(frame[a][a] * spacing[size_t(a)]);
  }
  for (double v : numbers("valid", size)) {
    if (v != 0.0 && v != 1.0) loader.fail(place + ".valid", "must hold 0 or 1 a probe");
    out.valid.push_back(uint8_t(v));
  }
  const std::vector<double> coefficients = numbers("coefficients", 27 * size);
  out.sh.resize(size);
  for (size_t p = 0; p < size; ++p)
    for (size_t k = 0; k < 27; ++k) out.sh[p][k / 3][int(k % 3)] = float(coefficients[27 * p + k]);
  return out;
}

// The .glb at `path` with its JSON chunk replaced by `json` (padded with spaces to 4 bytes, as
// the format asks); the other chunks are copied. check_glb_layout has passed.
std::string glb_with_json(const std::string& path, const std::string& json) {
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  uint32_t old_length;
  std::memcpy(&old_length, bytes.data() + 12, 4);
  const size_t rest_start = std::min<size_t>(20 + size_t(old_length), bytes.size());
  std::string padded = json;
  while (padded.size() % 4 != 0) padded += ' ';
  auto u32 = [](size_t value) {
    const uint32_t v = uint32_t(value);
    return std::string(reinterpret_cast<const char*>(&v), 4);
  };
  const std::string rest = bytes.substr(rest_start);
  return std::string("glTF", 4) + u32(2) + u32(12 + 8 + padded.size() + rest.size()) +
         u32(padded.size()) + std::string("JSON", 4) + padded + rest;
}

// The JSON text of a .gltf, or the JSON chunk of a .glb (whose layout check_glb_layout passed).
std::string json_text(const std::string& path, bool binary) {
  std::ifstream in(path, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (!binary) return bytes;
  if (bytes.size() < 20) return {};
  uint32_t length;
  std::memcpy(&length, bytes.data() + 12, 4);
  return bytes.substr(20, std::min<size_t>(length, bytes.size() - 20));
}

}  // namespace

LoadResult load_scene_gltf(const std::string& path, const SceneLoadOptions& options) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw SceneError(path + ": cannot open: no such file");
  if (!fs::is_regular_file(path, ec)) throw SceneError(path + ": cannot open: not a regular file");

  Loader loader;
  loader.path = path;
  tinygltf::TinyGLTF gltf;
  ImageDecodeLog decode_log;
  gltf.SetImageLoader(&decode_image_or_note, &decode_log);
  std::string error, warning;
  const bool binary = has_glb_magic(path);
  if (binary) check_glb_layout(path);
  // The JSON chunk of a .glb starts after the 12-byte header and its own 8-byte header.
  const GltfJsonSummary summary = precheck_gltf_json(path, json_text(path, binary), binary ? 20 : 0,
                                                     options.allow_outside_uris);
  bool ok = false;
  if (summary.stripped_json.empty()) {
    ok = binary ? gltf.LoadBinaryFromFile(&loader.model, &error, &warning, path)
                : gltf.LoadASCIIFromFile(&loader.model, &error, &warning, path);
  } else {
    // Parse the JSON with the animations cut out; buffers and images still resolve from here.
    const std::string base_dir = fs::path(path).parent_path().string();
    if (binary) {
      const std::string glb = glb_with_json(path, summary.stripped_json);
      ok = gltf.LoadBinaryFromMemory(&loader.model, &error, &warning,
                                     reinterpret_cast<const unsigned char*>(glb.data()),
                                     unsigned(glb.size()), base_dir);
    } else {
      ok = gltf.LoadASCIIFromString(&loader.model, &error, &warning, summary.stripped_json.data(),
                                    unsigned(summary.stripped_json.size()), base_dir);
    }
  }
  if (!ok || !error.empty()) {
    std::string message = one_line(error);
    if (message.empty()) message = "cannot parse glTF";
    throw SceneError(path + ": " + message);
  }
  loader.lightbake_export = loader.model.asset.generator.rfind("lightbake", 0) == 0;
  std::istringstream warning_lines(warning);
  for (std::string line; std::getline(warning_lines, line);)
    if (!one_line(line).empty()) loader.warnings.push_back(path + ": " + one_line(line));
  loader.image_failed.assign(loader.model.images.size(), false);
  for (const auto& [image, reason] : decode_log.failures) {
    if (image >= 0 && size_t(image) < loader.image_failed.size())
      loader.image_failed[size_t(image)] = true;
    loader.warn("images[" + std::to_string(image) + "]",
                "cannot decode image" + (reason.empty() ? std::string() : ": " + reason) +
                    "; texture ignored");
  }

  check_extensions(loader);
  loader.scene.source_path = path;
  loader.material_uvs.resize(loader.model.materials.size());
  for (size_t m = 0; m < loader.model.materials.size(); ++m)
    loader.scene.materials.push_back(convert_material(loader, int(m), loader.material_uvs[m]));

  const auto& model = loader.model;
  std::vector<std::pair<int, std::string>> roots;
  if (!model.scenes.empty()) {
    const int scene_index = model.defaultScene >= 0 ? model.defaultScene : 0;
    if (size_t(scene_index) >= model.scenes.size())
      loader.fail("scene", "scene " + std::to_string(scene_index) + " out of range (" +
                               std::to_string(model.scenes.size()) + " scenes)");
    if (model.scenes.size() > 1)
      loader.warn("scenes", "only scene " + std::to_string(scene_index) + " of " +
                                std::to_string(model.scenes.size()) + " loaded");
    const auto& nodes = model.scenes[size_t(scene_index)].nodes;
    for (size_t i = 0; i < nodes.size(); ++i)
      roots.emplace_back(
          nodes[i], "scenes[" + std::to_string(scene_index) + "].nodes[" + std::to_string(i) + "]");
  } else {
    // No scene: every node that is nobody's child is a root.
    std::vector<bool> is_child(model.nodes.size(), false);
    for (const auto& node : model.nodes)
      for (int child : node.children)
        if (child >= 0 && size_t(child) < is_child.size()) is_child[size_t(child)] = true;
    for (size_t n = 0; n < model.nodes.size(); ++n)
      if (!is_child[n]) roots.emplace_back(int(n), "nodes");
  }
  NodeWalker(loader).walk(roots);
  if (!model.scenes.empty()) {
    const int scene_index = model.defaultScene >= 0 ? model.defaultScene : 0;
    const auto& extensions = model.scenes[size_t(scene_index)].extensions;
    if (auto it = extensions.find("LIGHTBAKE_light_probes"); it != extensions.end()) {
      const dmat4 frame = roots.size() == 1 ? local_transform(loader,
                                                              model.nodes[size_t(roots[0].first)],
                                                              roots[0].first)
                                            : dmat4(1.0);
      loader.scene.probe_grid =
          read_probe_grid(loader, it->second, frame,
                          "scenes[" + std::to_string(scene_index) +
                              "].extensions.LIGHTBAKE_light_probes");
    }
  }
  if (loader.scene.meshes.empty()) loader.warn("scene", "no triangle meshes");
  warn_skipped(loader, summary);

  // Normal maps need tangents: MikkTSpace ones where the file has none, as glTF prescribes.
  for (Mesh& mesh : loader.scene.meshes) {
    const Material& material = loader.scene.materials[size_t(mesh.material)];
    if (material.bump != BumpKind::normal_map || !mesh.tangents.empty()) continue;
    if (mesh.uvs.empty())
      loader.warn("mesh '" + mesh.name + "'",
                  "normal map without its texture coordinates; bump ignored here");
    else
      generate_mikktspace_tangents(mesh);
  }

  LoadResult result;
  result.scene = std::move(loader.scene);
  result.warnings = std::move(loader.warnings);
  validate_scene(result.scene, result.warnings, {}, !options.included);
  return result;
}

}  // namespace lb
