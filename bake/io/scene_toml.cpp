// The native scene format: TOML (toml++), documented in docs/scene-format.md.
//
// Loading runs in two steps. First the file and its includes are parsed and merged by name
// into one view (materials, definitions, objects, cameras) of pointers into the parsed
// documents, so every value keeps its own file, line and column for messages. Then the view
// is built into a Scene: shapes and mesh files become world-space meshes, emitted power
// becomes radiance, and validate_scene checks the result.

#include <toml++/toml.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <deque>
#include <filesystem>
#include <fstream>
#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <map>
#include <numbers>
#include <optional>
#include <sstream>
#include <tuple>

#include "bake/input_file.h"
#include "bake/io/input_limits.h"
#include "bake/io/mesh_files.h"
#include "bake/io/scene_load.h"
#include "bake/io/scene_validate.h"
#include "bake/io/shapes.h"
#include "bake/io/textures.h"

namespace lb {

namespace {

namespace fs = std::filesystem;

// ---------------------------------------------------------------------------------------------
// Places and typed values

std::string location(const toml::source_region& source) {
  std::string text = source.path ? *source.path : std::string("?");
  if (source.begin.line > 0)
    text += ":" + std::to_string(source.begin.line) + ":" + std::to_string(source.begin.column);
  return text;
}

std::string type_name(const toml::node& node) {
  std::ostringstream out;
  out << node.type();
  return out.str();
}

std::string join_key(const std::string& path, std::string_view key) {
  return path.empty() ? std::string(key) : path + "." + std::string(key);
}

std::string format_number(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

// A TOML node together with the key path that leads to it, e.g. "objects[2].translate".
struct At {
  const toml::node* node = nullptr;
  std::string path;

  std::string where() const { return location(node->source()) + ": " + path; }
  [[noreturn]] void fail(const std::string& message) const {
    throw SceneError(where() + ": " + message);
  }
  // The directory relative paths in this node are resolved against: its own file's.
  fs::path directory() const {
    const auto& file = node->source().path;
    return file ? fs::path(*file).parent_path() : fs::path();
  }
  fs::path resolve(const std::string& relative) const {
    return (directory() / relative).lexically_normal();
  }
};

double read_double(const At& at) {
  double value = 0.0;
  if (const auto* i = at.node->as_integer())
    value = double(i->get());
  else if (const auto* f = at.node->as_floating_point())
    value = f->get();
  else
    at.fail("expected a number, got " + type_name(*at.node));
  if (!std::isfinite(value)) at.fail("value " + format_number(value) + " is not finite");
  return value;
}

float read_number(const At& at) {
  return float(read_double(at));
}

float read_positive(const At& at) {
  const float value = read_number(at);
  if (!(value > 0.0f)) at.fail("must be greater than 0, got " + format_number(value));
  return value;
}

float read_non_negative(const At& at) {
  const float value = read_number(at);
  if (value < 0.0f) at.fail("must not be negative, got " + format_number(value));
  return value;
}

int read_int(const At& at, int minimum, int maximum) {
  const auto* i = at.node->as_integer();
  if (!i) at.fail("expected an integer, got " + type_name(*at.node));
  const int64_t value = i->get();
  if (value < minimum || value > maximum)
    at.fail("must be in [" + std::to_string(minimum) + ", " + std::to_string(maximum) + "], got " +
            std::to_string(value));
  return int(value);
}

bool read_bool(const At& at) {
  const auto* b = at.node->as_boolean();
  if (!b) at.fail("expected true or false, got " + type_name(*at.node));
  return b->get();
}

std::string read_string(const At& at) {
  const auto* s = at.node->as_string();
  if (!s) at.fail("expected a string, got " + type_name(*at.node));
  return s->get();
}

template <int N>
glm::vec<N, float> read_vector(const At& at) {
  const auto* array = at.node->as_array();
  if (!array || array->size() != size_t(N))
    at.fail("expected an array of " + std::to_string(N) + " numbers, got " +
            (array ? "an array of " + std::to_string(array->size()) : type_name(*at.node)));
  glm::vec<N, float> v;
  for (int k = 0; k < N; ++k)
    v[k] = read_number(At{array->get(size_t(k)), at.path + "[" + std::to_string(k) + "]"});
  return v;
}

// A number (grey) or [r, g, b].
vec3 read_colour(const At& at) {
  if (at.node->is_array()) return read_vector<3>(at);
  if (!at.node->is_number())
    at.fail("expected a number or an array of 3 numbers, got " + type_name(*at.node));
  return vec3(read_number(at));
}

// A number (same on every axis) or a vector.
template <int N>
glm::vec<N, float> read_scalar_or_vector(const At& at) {
  if (at.node->is_array()) return read_vector<N>(at);
  if (!at.node->is_number())
    at.fail("expected a number or an array of " + std::to_string(N) + " numbers, got " +
            type_name(*at.node));
  return glm::vec<N, float>(read_number(at));
}

// A TOML table with its key path; `get` hands out its members as `At`.
struct TableAt {
  const toml::table* table = nullptr;
  std::string path;

  At at() const { return At{table, path}; }
  std::optional<At> get(std::string_view key) const {
    const toml::node* node = table->get(key);
    if (!node) return std::nullopt;
    return At{node, join_key(path, key)};
  }
  At require(std::string_view key) const {
    auto value = get(key);
    if (!value) at().fail("missing required key '" + std::string(key) + "'");
    return *value;
  }
  // Unknown keys are not fatal: a warning names each, so typos do not go unnoticed.
  void warn_unknown_keys(const std::vector<std::string_view>& allowed, const std::string& what,
                         std::vector<std::string>& warnings) const {
    for (auto&& [key, node] : *table) {
      if (std::find(allowed.begin(), allowed.end(), key.str()) != allowed.end()) continue;
      const toml::source_region& source =
          key.source().begin.line > 0 ? key.source() : node.source();
      warnings.push_back(location(source) + ": " + join_key(path, key.str()) + ": unknown key '" +
                         std::string(key.str()) + "' for " + what + " (ignored)");
    }
  }
};

TableAt require_table(const At& at) {
  const auto* table = at.node->as_table();
  if (!table) at.fail("expected a table, got " + type_name(*at.node));
  return TableAt{table, at.path};
}

const toml::array& require_array(const At& at) {
  const auto* array = at.node->as_array();
  if (!array) at.fail("expected an array, got " + type_name(*at.node));
  return *array;
}

// ---------------------------------------------------------------------------------------------
// Files

toml::table parse_toml_file(const std::string& path, const std::string& where) {
  if (const std::string problem = input_file_problem(path); !problem.empty())
    throw SceneError(where + "scene file '" + path + "' " + problem);
  if (!std::ifstream(path))
    throw SceneError(where + "cannot read scene file '" + path + "' (permission denied?)");
  try {
    return toml::parse_file(path);
  } catch (const toml::parse_error& e) {
    std::string description(e.description());
    std::replace(description.begin(), description.end(), '\n', ' ');
    throw SceneError(location(e.source()) + ": TOML syntax error: " + description);
  }
}

glm::mat4 rotation_to(vec3 from, vec3 to) {
  from = glm::normalize(from);
  to = glm::normalize(to);
  const float cosine = glm::dot(from, to);
  if (cosine > 0.999999f) return glm::mat4(1.0f);
  if (cosine < -0.999999f) {
    const vec3 axis = std::abs(from.x) < 0.9f ? vec3(1, 0, 0) : vec3(0, 0, 1);
    return glm::rotate(glm::mat4(1.0f), glm::pi<float>(), glm::normalize(glm::cross(from, axis)));
  }
  return glm::rotate(glm::mat4(1.0f), std::acos(cosine), glm::normalize(glm::cross(from, to)));
}

// ---------------------------------------------------------------------------------------------
// The loader

constexpr int kMaxIncludeDepth = 16;

// What a part inherits from the instance that places it.
struct Inherited {
  glm::mat4 transform{1.0f};
  std::string material;  // empty: none
  MeshBakeSettings bake;
  std::string name_prefix;
  bool dynamic = false;  // a moving object, lit by the light probes (Mesh::dynamic)
};

class TomlSceneLoader {
 public:
  explicit TomlSceneLoader(std::string path) : top_path_(std::move(path)) {}

  LoadResult load() {
    collect(top_path_, 0, "");
    build();
    result_.scene.source_path = top_path_;
    validate_scene(result_.scene, result_.warnings, mesh_places_);
    return std::move(result_);
  }

 private:
  // ---- Step 1: parse and merge the file and its includes ------------------------------------

  void collect(const std::string& path, int depth, const std::string& where) {
    if (depth > kMaxIncludeDepth)
      throw SceneError(where + "includes nested deeper than " + std::to_string(kMaxIncludeDepth) +
                       " levels (a cycle?)");
    std::error_code error;
    std::string canonical = fs::weakly_canonical(path, error).string();
    if (error) canonical = fs::absolute(path, error).lexically_normal().string();
    if (std::find(include_chain_.begin(), include_chain_.end(), canonical) != include_chain_.end())
      throw SceneError(where + "include cycle: '" + path + "' includes itself");
    // A glTF file is not TOML (a .glb is binary): its own loader reads it, and build() puts its
    // meshes, materials, cameras and lamps in first, so this file can add a sky, lights,
    // objects and bake settings (docs/gltf.md).
    if (is_gltf_path(path)) {
      try {
        gltf_includes_.push_back(load_scene_gltf(path, {.included = true}));
      } catch (const SceneError& e) {
        throw SceneError(where + e.what());
      }
      return;
    }
    documents_.push_back(parse_toml_file(path, where));
    const TableAt root{&documents_.back(), ""};
    include_chain_.push_back(canonical);
    root.warn_unknown_keys({"description", "include", "remove", "materials", "define", "objects",
                            "cameras", "lights", "sky", "bake"},
                           "a scene file", result_.warnings);

    if (auto include = root.get("include")) {
      std::vector<At> files;
      if (include->node->is_array()) {
        const toml::array& array = require_array(*include);
        for (size_t k = 0; k < array.size(); ++k)
          files.push_back(At{array.get(k), include->path + "[" + std::to_string(k) + "]"});
      } else {
        files.push_back(*include);
      }
      for (const At& file : files)
        collect(file.resolve(read_string(file)).string(), depth + 1, file.where() + ": ");
    }
    if (auto remove = root.get("remove")) {
      const toml::array& names = require_array(*remove);
      for (size_t k = 0; k < names.size(); ++k) {
        const At name_at{names.get(k), remove->path + "[" + std::to_string(k) + "]"};
        const std::string name = read_string(name_at);
        auto it = std::find_if(objects_.begin(), objects_.end(),
                               [&](const Named& o) { return o.name == name; });
        if (it != objects_.end())
          objects_.erase(it);
        else if (!remove_gltf_meshes(name))
          name_at.fail("no included object named '" + name + "'");
      }
    }
    if (auto materials = root.get("materials")) {
      for (auto&& [key, node] : *require_table(*materials).table) {
        const At at{&node, join_key("materials", key.str())};
        const TableAt table = require_table(at);
        const std::string name(key.str());
        if (!materials_.count(name)) material_order_.push_back(name);
        materials_[name] = table;
      }
    }
    if (auto define = root.get("define")) {
      for (auto&& [key, node] : *require_table(*define).table) {
        const At at{&node, join_key("define", key.str())};
        require_array(at);
        definitions_[std::string(key.str())] = at;
      }
    }
    if (auto bake = root.get("bake")) read_bake_settings(require_table(*bake));
    merge_named_tables(root, "objects", objects_);
    merge_named_tables(root, "cameras", cameras_);
    merge_named_tables(root, "lights", lights_);
    if (auto sky = root.get("sky")) sky_ = require_table(*sky);
    include_chain_.pop_back();
  }

  static bool is_gltf_path(const std::string& path) {
    const std::string extension = lowercase_extension(path);
    return extension == ".gltf" || extension == ".glb";
  }

  // `remove` on an included glTF: its meshes are named NODE or NODE/MESH.K, so a node's name
  // removes all of its primitives.
  bool remove_gltf_meshes(const std::string& name) {
    bool removed = false;
    for (LoadResult& gltf : gltf_includes_)
      std::erase_if(gltf.scene.meshes, [&](const Mesh& mesh) {
        const bool match = mesh.name == name || mesh.name.starts_with(name + "/");
        removed = removed || match;
        return match;
      });
    return removed;
  }

  // The included glTF scenes, first: their materials become named materials of this file (a
  // TOML material of the same name replaces one), texture and material indices shifted.
  void merge_gltf_includes() {
    Scene& scene = result_.scene;
    for (LoadResult& gltf : gltf_includes_) {
      const int texture_base = int(scene.textures.size());
      const int material_base = int(scene.materials.size());
      for (Texture& texture : gltf.scene.textures) scene.textures.push_back(std::move(texture));
      for (Material material : gltf.scene.materials) {
        for (int* index : {&material.reflectance_texture, &material.bump_texture})
          if (*index >= 0) *index += texture_base;
        material_index_[material.name] = int(scene.materials.size());
        scene.materials.push_back(std::move(material));
        material_power_.push_back(std::nullopt);
      }
      for (Mesh& mesh : gltf.scene.meshes) {
        mesh.material += material_base;
        scene.meshes.push_back(std::move(mesh));
        mesh_places_.push_back(gltf.scene.source_path);
      }
      for (Camera& camera : gltf.scene.cameras) scene.cameras.push_back(std::move(camera));
      for (Lamp& lamp : gltf.scene.lights) scene.lights.push_back(std::move(lamp));
      if (gltf.scene.sky) scene.sky = gltf.scene.sky;
      for (std::string& warning : gltf.warnings) result_.warnings.push_back(std::move(warning));
    }
  }

  // `[bake]`: settings of the whole bake (an including file's win over an included one's).
  void read_bake_settings(const TableAt& bake) {
    for (auto&& [key, node] : *bake.table) {
      const At at{&node, join_key(bake.path, key.str())};
      if (key.str() == "quality") {
        try {
          result_.scene.quality = parse_quality(read_string(at));
        } catch (const std::invalid_argument& e) {
          at.fail(e.what());
        }
        continue;
      }
      // Every other key is a setting of the table in bake/pipeline/bake_settings.h, which
      // checks name and range when a bake resolves its settings.
      const double value = node.is_boolean() ? double(read_bool(at)) : read_double(at);
      auto& settings = result_.scene.bake_settings;
      auto same = std::find_if(settings.begin(), settings.end(),
                               [&](const auto& s) { return s.key == key.str(); });
      const Scene::BakeSettingValue setting{std::string(key.str()), value, at.where()};
      if (same == settings.end())
        settings.push_back(setting);
      else
        *same = setting;
    }
  }

  struct Named {
    std::string name;  // empty when unnamed
    TableAt table;
  };

  // Appends an array of tables; an entry whose name matches an included one replaces it.
  void merge_named_tables(const TableAt& root, std::string_view key, std::vector<Named>& into) {
    auto list = root.get(key);
    if (!list) return;
    const toml::array& array = require_array(*list);
    for (size_t k = 0; k < array.size(); ++k) {
      const At at{array.get(k), std::string(key) + "[" + std::to_string(k) + "]"};
      Named entry{"", require_table(at)};
      if (auto name = entry.table.get("name")) entry.name = read_string(*name);
      auto same = std::find_if(into.begin(), into.end(), [&](const Named& n) {
        return !entry.name.empty() && n.name == entry.name;
      });
      if (same != into.end())
        *same = entry;
      else
        into.push_back(entry);
    }
  }

  // ---- Step 2: build the scene --------------------------------------------------------------

  void build() {
    merge_gltf_includes();
    for (const std::string& name : material_order_) build_material(name, materials_.at(name));
    for (const Named& object : objects_) {
      std::vector<std::string> chain;
      build_object(object.table, Inherited{}, chain);
    }
    convert_power_to_radiance();
    for (Mesh& mesh : result_.scene.meshes)
      if (result_.scene.materials[size_t(mesh.material)].bump != BumpKind::none)
        compute_tangents(mesh);
    for (const Named& camera : cameras_) build_camera(camera.table);
    for (const Named& light : lights_) build_lamp(light.table);
    if (sky_) build_sky(*sky_);
  }

  // ---- Materials

  // `sky_degrees`: an equirect sky turned about +Y (rotated_equirect), a texture of its own.
  int texture(const At& at, bool srgb, double sky_degrees = 0.0) {
    const std::string path = at.resolve(read_string(at)).string();
    const auto key = std::make_tuple(path, srgb, sky_degrees);
    if (auto it = texture_index_.find(key); it != texture_index_.end()) return it->second;
    Texture loaded = load_texture_file(path, srgb, at.where());
    result_.scene.textures.push_back(sky_degrees == 0.0 ? std::move(loaded)
                                                        : rotated_equirect(loaded, sky_degrees));
    const int index = int(result_.scene.textures.size()) - 1;
    texture_index_[key] = index;
    return index;
  }

  void build_material(const std::string& name, const TableAt& t) {
    Material m;
    m.name = name;
    std::string type = "diffuse";
    std::optional<At> type_at = t.get("type");
    if (type_at) type = read_string(*type_at);
    std::vector<std::string_view> keys = {"type", "emission", "power", "double_sided", "group"};
    if (type == "diffuse") {
      m.kind = MaterialKind::diffuse;
      keys.insert(keys.end(), {"reflectance", "texture", "bump"});
    } else if (type == "mirror") {
      m.kind = MaterialKind::mirror;
      m.reflectance = vec3(0.95f);
      keys.push_back("reflectance");
    } else if (type == "glass") {
      m.kind = MaterialKind::glass;
      m.reflectance = vec3(1.0f);
      keys.insert(keys.end(), {"transmittance", "ior"});
    } else if (type == "glossy") {
      m.kind = MaterialKind::glossy;
      m.reflectance = vec3(0.9f);
      m.roughness = 0.2f;
      keys.insert(keys.end(), {"reflectance", "roughness"});
    } else {
      type_at->fail("unknown material type '" + type +
                    "' (expected diffuse, mirror, glass or glossy)");
    }
    t.warn_unknown_keys(keys, "a " + type + " material", result_.warnings);
    auto has_key = [&](std::string_view key) {
      return std::find(keys.begin(), keys.end(), key) != keys.end();
    };
    auto colour_in_unit_range = [](const At& at, const char* what) {
      const vec3 c = read_colour(at);
      if (glm::any(glm::lessThan(c, vec3(0.0f))) || glm::any(glm::greaterThan(c, vec3(1.0f))))
        at.fail(std::string(what) + " (" + format_number(c.x) + ", " + format_number(c.y) + ", " +
                format_number(c.z) + ") is outside [0, 1]");
      return c;
    };
    if (auto texture_at = has_key("texture") ? t.get("texture") : std::nullopt) {
      m.reflectance = vec3(1.0f);  // the texture alone sets the colour unless both are given
      m.reflectance_texture = texture(*texture_at, true);
    }
    if (auto r = has_key("reflectance") ? t.get("reflectance") : std::nullopt)
      m.reflectance = colour_in_unit_range(*r, "reflectance");
    if (auto r = has_key("transmittance") ? t.get("transmittance") : std::nullopt)
      m.reflectance = colour_in_unit_range(*r, "transmittance");
    if (auto ior = has_key("ior") ? t.get("ior") : std::nullopt) {
      m.ior = read_number(*ior);
      if (m.ior < 1.0f) ior->fail("index of refraction " + format_number(m.ior) + " is below 1");
    }
    if (auto roughness = has_key("roughness") ? t.get("roughness") : std::nullopt) {
      m.roughness = read_number(*roughness);
      if (!(m.roughness > 0.0f && m.roughness <= 1.0f))
        roughness->fail("roughness " + format_number(m.roughness) +
                        " is outside (0, 1] (use a mirror for 0)");
    }
    auto emission = t.get("emission");
    auto power = t.get("power");
    if (emission && power) power->fail("give either 'emission' or 'power', not both");
    auto non_negative_colour = [](const At& at, const char* what) {
      const vec3 c = read_colour(at);
      if (glm::any(glm::lessThan(c, vec3(0.0f))))
        at.fail(std::string("negative ") + what + " (" + format_number(c.x) + ", " +
                format_number(c.y) + ", " + format_number(c.z) + ")");
      return c;
    };
    if (emission) m.emission = non_negative_colour(*emission, "radiance");
    if (auto group = t.get("group")) m.light_group = read_group(*group);
    if (auto sides = t.get("double_sided")) {  // glTF's doubleSided: both faces emit and reflect
      m.two_sided_emission = read_bool(*sides);
      m.two_sided_reflection = m.two_sided_emission && m.is_diffuse();
    }
    std::optional<PendingPower> pending;
    if (power) pending = PendingPower{non_negative_colour(*power, "power"), *power};
    if (auto bump = has_key("bump") ? t.get("bump") : std::nullopt) read_bump(m, *bump);
    if (auto from_gltf = material_index_.find(name); from_gltf != material_index_.end()) {
      result_.scene.materials[size_t(from_gltf->second)] = m;  // replaces an included glTF's
      material_power_[size_t(from_gltf->second)] = pending;
      return;
    }
    material_index_[name] = int(result_.scene.materials.size());
    result_.scene.materials.push_back(m);
    material_power_.push_back(pending);
  }

  void read_bump(Material& m, const At& at) {
    const TableAt bump = require_table(at);
    bump.warn_unknown_keys({"height", "normal", "scale"}, "a bump map", result_.warnings);
    auto height = bump.get("height");
    auto normal = bump.get("normal");
    if (height && normal) normal->fail("give either 'height' or 'normal', not both");
    if (!height && !normal) at.fail("a bump map needs 'height' or 'normal' (a texture file)");
    m.bump = height ? BumpKind::height : BumpKind::normal_map;
    m.bump_scale = height ? 0.005f : 1.0f;
    m.bump_texture = texture(height ? *height : *normal, false);
    if (auto scale = bump.get("scale")) m.bump_scale = read_number(*scale);
  }

  // A material given in watts: each mesh using it emits that power from its front side,
  // radiance = power / (pi * area), or from both sides of a double-sided material, half from
  // each. Meshes of different area get their own copy.
  void convert_power_to_radiance() {
    Scene& scene = result_.scene;
    const size_t material_count = scene.materials.size();
    for (size_t m = 0; m < material_count && m < material_power_.size(); ++m) {
      if (!material_power_[m]) continue;
      const PendingPower& power = *material_power_[m];
      float first_area = -1.0f;
      for (Mesh& mesh : scene.meshes) {
        if (mesh.material != int(m)) continue;
        const float area = mesh_area(mesh);
        if (!(area > 0.0f))
          power.at.fail("mesh '" + mesh.name + "' has zero area and cannot emit power");
        const float sides = scene.materials[m].two_sided_emission ? 2.0f : 1.0f;
        const vec3 radiance = power.watts / (sides * glm::pi<float>() * area);
        if (first_area < 0.0f) {
          first_area = area;
          scene.materials[m].emission = radiance;
        } else if (std::abs(area - first_area) > 1e-6f * first_area) {
          Material copy = scene.materials[m];
          copy.name += "@" + mesh.name;
          copy.emission = radiance;
          mesh.material = int(scene.materials.size());
          scene.materials.push_back(copy);
        }
      }
    }
  }

  // ---- Objects

  int material_by_name(const At& at, const std::string& name) {
    if (auto it = material_index_.find(name); it != material_index_.end()) return it->second;
    std::string known;
    for (const std::string& n : material_order_) known += (known.empty() ? "" : ", ") + n;
    at.fail("no material named '" + name + "' (defined: " + (known.empty() ? "none" : known) + ")");
  }

  int default_material() {
    if (default_material_ < 0) {
      Material m;
      m.name = "default";
      default_material_ = int(result_.scene.materials.size());
      result_.scene.materials.push_back(m);
      material_power_.push_back(std::nullopt);
    }
    return default_material_;
  }

  static glm::mat4 read_transform(const TableAt& t) {
    glm::mat4 transform(1.0f);
    if (auto translate = t.get("translate"))
      transform = glm::translate(transform, read_vector<3>(*translate));
    if (auto rotate = t.get("rotate")) {
      if (rotate->node->is_table()) {
        const TableAt r = require_table(*rotate);
        const vec3 axis = read_vector<3>(r.require("axis"));
        const float angle = read_number(r.require("angle"));
        if (glm::length(axis) == 0.0f) r.require("axis").fail("rotation axis is zero");
        transform = glm::rotate(transform, glm::radians(angle), glm::normalize(axis));
      } else {
        // Euler angles in degrees, applied about X, then Y, then Z.
        const vec3 degrees = read_vector<3>(*rotate);
        transform = glm::rotate(transform, glm::radians(degrees.z), vec3(0, 0, 1));
        transform = glm::rotate(transform, glm::radians(degrees.y), vec3(0, 1, 0));
        transform = glm::rotate(transform, glm::radians(degrees.x), vec3(1, 0, 0));
      }
    }
    if (auto scale = t.get("scale")) {
      const vec3 s = read_scalar_or_vector<3>(*scale);
      if (s.x == 0.0f || s.y == 0.0f || s.z == 0.0f) scale->fail("scale must not be zero");
      transform = glm::scale(transform, s);
    }
    return transform;
  }

  void build_object(const TableAt& t, const Inherited& parent, std::vector<std::string>& chain) {
    std::vector<std::string_view> keys = {"name",     "material",   "translate",      "rotate",
                                          "scale",    "texel_size", "texel_density",  "patch_size",
                                          "uv_scale", "flip",       "caustic_origins", "dynamic"};
    auto shape = t.get("shape");
    auto file = t.get("mesh");
    auto instance = t.get("instance");
    const int kinds = (shape ? 1 : 0) + (file ? 1 : 0) + (instance ? 1 : 0);
    if (kinds != 1) t.at().fail("an object needs exactly one of 'shape', 'mesh' or 'instance'");

    Inherited here;
    here.transform = parent.transform * read_transform(t);
    here.material = parent.material;
    if (auto material = t.get("material")) {
      here.material = read_string(*material);
      material_by_name(*material, here.material);  // fails early, at the key, if unknown
    }
    here.bake = parent.bake;
    here.dynamic = parent.dynamic;
    if (auto dynamic = t.get("dynamic")) here.dynamic = read_bool(*dynamic);
    if (auto texel = t.get("texel_size")) here.bake.texel_size = read_positive(*texel);
    if (auto density = t.get("texel_density")) {  // texels per metre, the engines' unit
      if (t.get("texel_size")) density->fail("give 'texel_size' or 'texel_density', not both");
      here.bake.texel_size = 1.0f / read_positive(*density);
    }
    if (auto patch = t.get("patch_size")) here.bake.patch_size = read_positive(*patch);
    if (auto origins = t.get("caustic_origins")) {
      const std::string value = read_string(*origins);
      if (value == "centre" || value == "center")
        here.bake.caustic_origins = CausticOrigins::centre;
      else if (value == "area")
        here.bake.caustic_origins = CausticOrigins::over_light;
      else
        origins->fail("caustic_origins is 'centre' or 'area', not '" + value + "'");
    }
    std::string name = t.path;
    if (auto n = t.get("name")) name = read_string(*n);
    here.name_prefix = parent.name_prefix + name + "/";

    if (instance) {
      keys.push_back("instance");
      t.warn_unknown_keys(keys, "an instance", result_.warnings);
      const std::string definition = read_string(*instance);
      auto it = definitions_.find(definition);
      if (it == definitions_.end()) instance->fail("no definition named '" + definition + "'");
      if (std::find(chain.begin(), chain.end(), definition) != chain.end())
        instance->fail("definition '" + definition + "' places itself (a cycle)");
      if (chain.size() >= size_t(limits::kMaxInstanceDepth))
        instance->fail("instances nested deeper than " + std::to_string(limits::kMaxInstanceDepth) +
                       " levels (bake/io/input_limits.h)");
      // Count before expanding: ten levels of ten copies is 10^10 objects, and as many empty
      // instances would be as much work.
      const uint64_t objects = objects_placed_by(definition, 0);
      if (objects > limits::kMaxInstances - std::min(objects_placed_, limits::kMaxInstances))
        instance->fail(
            "definition '" + definition + "' places " +
            (objects == UINT64_MAX ? std::string("over 2^64") : std::to_string(objects)) +
            " objects and instances; with the " + std::to_string(objects_placed_) +
            " before it that exceeds " + std::to_string(limits::kMaxInstances) +
            " (bake/io/input_limits.h)");
      ++objects_placed_;
      chain.push_back(definition);
      const toml::array& parts = require_array(it->second);
      for (size_t k = 0; k < parts.size(); ++k)
        build_object(
            require_table(At{parts.get(k), it->second.path + "[" + std::to_string(k) + "]"}), here,
            chain);
      chain.pop_back();
      return;
    }

    std::vector<ShapePart> parts;
    bool inward = false;
    if (file) {
      keys.push_back("mesh");
      keys.push_back("crease_angle");
      t.warn_unknown_keys(keys, "a mesh object", result_.warnings);
      float crease = 30.0f;
      if (auto c = t.get("crease_angle")) crease = read_non_negative(*c);
      const std::string path = file->resolve(read_string(*file)).string();
      const std::string cache_key = path + "|" + std::to_string(crease);
      auto cached = mesh_file_cache_.find(cache_key);
      if (cached == mesh_file_cache_.end())
        cached =
            mesh_file_cache_
                .emplace(cache_key, read_mesh_file(path, crease, file->where(), result_.warnings))
                .first;
      parts.push_back(ShapePart{cached->second, "", ""});
    } else {
      parts = build_shape(t, *shape, keys, inward);
    }
    std::optional<vec2> uv_scale;
    if (auto at = t.get("uv_scale")) uv_scale = read_scalar_or_vector<2>(*at);
    bool flip = inward;
    if (auto f = t.get("flip")) flip = flip != read_bool(*f);
    for (ShapePart& part : parts) {
      Mesh& mesh = part.mesh;
      if (uv_scale)
        for (vec2& uv : mesh.uvs) uv *= *uv_scale;
      if (flip) flip_mesh(mesh);
      transform_mesh(mesh, here.transform);
      mesh.name = parent.name_prefix + name + part.suffix;
      const std::string& material = part.material.empty() ? here.material : part.material;
      mesh.material = material.empty() ? default_material() : material_by_name(t.at(), material);
      mesh.bake = here.bake;
      mesh.dynamic = here.dynamic;
      triangles_placed_ += mesh.triangles.size();
      if (triangles_placed_ > limits::kMaxTriangles)
        t.at().fail("the scene holds more than " + std::to_string(limits::kMaxTriangles) +
                    " triangles here (bake/io/input_limits.h)");
      result_.scene.meshes.push_back(std::move(mesh));
      mesh_places_.push_back(t.at().where());
    }
    ++objects_placed_;
  }

  // Objects (shapes, mesh files and instances) that placing `definition` places, without
  // building them; saturates at UINT64_MAX. Cycles and depth are reported by build_object.
  uint64_t objects_placed_by(const std::string& definition, int depth) {
    if (auto known = placed_by_definition_.find(definition); known != placed_by_definition_.end())
      return known->second;
    auto it = definitions_.find(definition);
    if (it == definitions_.end() || depth > limits::kMaxInstanceDepth) return 0;
    const toml::array* parts = it->second.node->as_array();
    if (!parts) return 0;
    placed_by_definition_[definition] = 0;  // a cycle back here counts nothing
    uint64_t total = 0;
    for (const toml::node& part : *parts) {
      const toml::table* table = part.as_table();
      const toml::node* instance = table ? table->get("instance") : nullptr;
      uint64_t count = 1;
      if (instance && instance->is_string()) {
        const uint64_t inside =
            objects_placed_by(std::string(*instance->value<std::string>()), depth + 1);
        count = inside == UINT64_MAX ? UINT64_MAX : inside + 1;
      }
      total = total > UINT64_MAX - count ? UINT64_MAX : total + count;
    }
    placed_by_definition_[definition] = total;
    return total;
  }

  struct ShapePart {
    Mesh mesh;
    std::string suffix;    // appended to the object's name when a shape makes several meshes
    std::string material;  // empty: the object's
  };

  // A box whose faces carry different materials (a room): one mesh per material.
  std::vector<ShapePart> split_box_faces(const At& at, std::array<Mesh, 6> faces) {
    static const char* const kAxisNames[6] = {"-x", "+x", "-y", "+y", "-z", "+z"};
    static const char* const kRoomNames[6] = {"left", "right", "floor", "ceiling", "back", "front"};
    std::string face_material[6];
    for (auto&& [key, node] : *require_table(at).table) {
      const At value{&node, join_key(at.path, key.str())};
      int face = -1;
      for (int f = 0; f < 6; ++f)
        if (key.str() == kAxisNames[f] || key.str() == kRoomNames[f]) face = f;
      if (face < 0)
        value.fail("unknown box face '" + std::string(key.str()) +
                   "' (expected -x, +x, -y, +y, -z, +z or left, right, floor, ceiling, back, "
                   "front)");
      face_material[face] = read_string(value);
      material_by_name(value, face_material[face]);
    }
    std::vector<ShapePart> parts;
    bool used[6] = {};
    for (int f = 0; f < 6; ++f) {
      if (used[f]) continue;
      ShapePart part{Mesh{}, "", face_material[f]};
      for (int g = f; g < 6; ++g) {
        if (used[g] || face_material[g] != face_material[f]) continue;
        used[g] = true;
        append_mesh(part.mesh, faces[size_t(g)]);
        part.suffix += (part.suffix.empty() ? "" : ",") + std::string(kRoomNames[g]);
      }
      part.suffix = "[" + part.suffix + "]";
      parts.push_back(std::move(part));
    }
    return parts;
  }

  std::vector<ShapePart> build_shape(const TableAt& t, const At& shape_at,
                                     std::vector<std::string_view>& keys, bool& inward) {
    const std::string shape = read_string(shape_at);
    keys.push_back("shape");
    auto number_or = [&](std::string_view key, float fallback, auto reader) {
      auto at = t.get(key);
      return at ? reader(*at) : fallback;
    };
    auto int_or = [&](std::string_view key, int fallback, int minimum) {
      auto at = t.get(key);
      return at ? read_int(*at, minimum, 4096) : fallback;
    };
    auto read_inward = [&] {
      keys.push_back("inward");
      if (auto at = t.get("inward")) inward = read_bool(*at);
    };
    Mesh mesh;
    if (shape == "quad") {
      keys.insert(keys.end(), {"size", "normal", "corner", "edge_u", "edge_v", "uv_tile"});
      t.warn_unknown_keys(keys, "a quad", result_.warnings);
      const float tile = number_or("uv_tile", 0.0f, read_non_negative);
      if (auto corner = t.get("corner")) {
        const vec3 u = read_vector<3>(t.require("edge_u"));
        const vec3 v = read_vector<3>(t.require("edge_v"));
        if (glm::length(glm::cross(u, v)) == 0.0f)
          t.require("edge_v").fail("edges are parallel or zero: the quad has no area");
        mesh = make_quad_corners(read_vector<3>(*corner), u, v, tile);
      } else {
        vec2 size(1.0f);
        if (auto s = t.get("size")) {
          size = read_scalar_or_vector<2>(*s);
          if (!(size.x > 0.0f && size.y > 0.0f)) s->fail("quad size must be positive");
        }
        mesh = make_quad(size, tile);
        if (auto normal = t.get("normal")) {
          const vec3 n = read_vector<3>(*normal);
          if (glm::length(n) == 0.0f) normal->fail("normal is zero");
          transform_mesh(mesh, rotation_to(vec3(0, 1, 0), n));
        }
      }
    } else if (shape == "box") {
      keys.insert(keys.end(), {"size", "min", "max", "uv_tile", "face_materials"});
      read_inward();
      t.warn_unknown_keys(keys, "a box", result_.warnings);
      vec3 lo(-0.5f), hi(0.5f);
      if (auto size = t.get("size")) {
        const vec3 s = read_scalar_or_vector<3>(*size);
        if (!(s.x > 0.0f && s.y > 0.0f && s.z > 0.0f)) size->fail("box size must be positive");
        lo = -0.5f * s;
        hi = 0.5f * s;
      } else if (t.get("min") || t.get("max")) {
        lo = read_vector<3>(t.require("min"));
        hi = read_vector<3>(t.require("max"));
        if (!(hi.x > lo.x && hi.y > lo.y && hi.z > lo.z))
          t.require("max").fail("box max must exceed min on every axis");
      }
      const float tile = number_or("uv_tile", 0.0f, read_non_negative);
      if (auto faces = t.get("face_materials"))
        return split_box_faces(*faces, make_box_faces(lo, hi, tile));
      mesh = make_box(lo, hi, tile);
    } else if (shape == "sphere") {
      keys.insert(keys.end(), {"radius", "rings", "segments"});
      read_inward();
      t.warn_unknown_keys(keys, "a sphere", result_.warnings);
      mesh = make_sphere(number_or("radius", 1.0f, read_positive), int_or("rings", 32, 2),
                         int_or("segments", 64, 3));
    } else if (shape == "cylinder") {
      keys.insert(keys.end(), {"radius", "inner_radius", "height", "segments", "caps"});
      read_inward();
      t.warn_unknown_keys(keys, "a cylinder", result_.warnings);
      const float radius = number_or("radius", 1.0f, read_positive);
      const float inner = number_or("inner_radius", 0.0f, read_non_negative);
      if (inner >= radius) t.require("inner_radius").fail("inner_radius must be below radius");
      bool caps = true;
      if (auto c = t.get("caps")) caps = read_bool(*c);
      mesh = make_cylinder(radius, inner, number_or("height", 1.0f, read_positive),
                           int_or("segments", 64, 3), caps);
    } else if (shape == "torus") {
      keys.insert(keys.end(), {"major_radius", "minor_radius", "rings", "segments"});
      read_inward();
      t.warn_unknown_keys(keys, "a torus", result_.warnings);
      const float major = number_or("major_radius", 1.0f, read_positive);
      const float minor = number_or("minor_radius", 0.25f, read_positive);
      if (minor >= major) t.require("minor_radius").fail("minor_radius must be below major_radius");
      mesh = make_torus(major, minor, int_or("rings", 32, 3), int_or("segments", 64, 3));
    } else if (shape == "revolution") {
      keys.insert(keys.end(), {"profile", "thickness", "segments", "crease_angle"});
      read_inward();
      t.warn_unknown_keys(keys, "a surface of revolution", result_.warnings);
      const At profile_at = t.require("profile");
      const toml::array& points = require_array(profile_at);
      if (points.size() < 2) profile_at.fail("a profile needs at least 2 points");
      std::vector<vec2> profile;
      for (size_t k = 0; k < points.size(); ++k) {
        const At point{points.get(k), profile_at.path + "[" + std::to_string(k) + "]"};
        profile.push_back(read_vector<2>(point));
        if (profile.back().x < 0.0f) point.fail("profile radius must not be negative");
      }
      mesh = make_revolution(profile, number_or("thickness", 0.0f, read_non_negative),
                             int_or("segments", 64, 3),
                             number_or("crease_angle", 30.0f, read_non_negative));
      if (mesh.triangles.empty()) profile_at.fail("the profile encloses no area when revolved");
    } else {
      shape_at.fail("unknown shape '" + shape +
                    "' (expected quad, box, sphere, cylinder, torus or revolution)");
    }
    return {ShapePart{std::move(mesh), "", ""}};
  }

  // ---- Cameras

  void build_camera(const TableAt& t) {
    t.warn_unknown_keys(
        {"name", "position", "target", "up", "fov", "aperture", "focus_distance", "exposure"},
        "a camera", result_.warnings);
    Camera camera;
    camera.name = "camera" + std::to_string(result_.scene.cameras.size());
    if (auto name = t.get("name")) camera.name = read_string(*name);
    if (auto p = t.get("position")) camera.position = read_vector<3>(*p);
    if (auto p = t.get("target")) camera.target = read_vector<3>(*p);
    if (auto p = t.get("up")) camera.up = read_vector<3>(*p);
    if (auto fov = t.get("fov")) {
      camera.vertical_fov_deg = read_number(*fov);
      if (!(camera.vertical_fov_deg > 0.0f && camera.vertical_fov_deg < 180.0f))
        fov->fail("field of view must be in (0, 180) degrees");
    }
    if (auto a = t.get("aperture")) camera.aperture_radius = read_non_negative(*a);
    if (auto f = t.get("focus_distance")) camera.focus_distance = read_non_negative(*f);
    if (auto e = t.get("exposure")) {
      camera.exposure = read_number(*e);
      if (!(std::abs(camera.exposure) <= 64.0f)) e->fail("exposure must be in [-64, 64] stops");
    }
    if (glm::length(camera.target - camera.position) == 0.0f)
      t.at().fail("camera target equals its position");
    if (glm::length(glm::cross(camera.target - camera.position, camera.up)) == 0.0f)
      t.at().fail("camera up is parallel to its viewing direction");
    result_.scene.cameras.push_back(camera);
  }

  // ---- Lights (docs/scene-format.md): point, spot and directional lamps; the sky

  void build_lamp(const TableAt& t) {
    Lamp lamp;
    lamp.name = "light" + std::to_string(result_.scene.lights.size());
    if (auto name = t.get("name")) lamp.name = read_string(*name);
    const At type_at = t.require("type");
    const std::string type = read_string(type_at);
    std::vector<std::string_view> keys = {"name", "type", "colour", "group"};
    if (type == "point") {
      lamp.kind = LampKind::point;
      keys.insert(keys.end(), {"position", "power", "intensity", "candela", "range"});
    } else if (type == "spot") {
      lamp.kind = LampKind::spot;
      keys.insert(keys.end(), {"position", "target", "direction", "power", "intensity", "candela",
                               "range", "inner_angle", "outer_angle"});
    } else if (type == "directional" || type == "sun") {
      lamp.kind = LampKind::directional;
      keys.insert(keys.end(), {"direction", "irradiance", "lux"});
    } else {
      type_at.fail("unknown light type '" + type + "' (expected point, spot or directional)");
    }
    t.warn_unknown_keys(keys, "a " + type + " light", result_.warnings);
    if (auto group = t.get("group")) lamp.light_group = read_group(*group);
    vec3 colour(1.0f);
    if (auto c = t.get("colour")) {
      colour = read_colour(*c);
      if (glm::any(glm::lessThan(colour, vec3(0.0f)))) c->fail("colour must not be negative");
    }
    // Exactly one strength: radiometric (W, W/sr, W/m^2) or photometric (cd, lx at 683 lm/W).
    const std::vector<std::pair<const char*, double>> strengths =
        lamp.kind == LampKind::directional
            ? std::vector<std::pair<const char*, double>>{{"irradiance", 1.0},
                                                          {"lux", 1.0 / kLumensPerWatt}}
            // Power as Blender gives it: a spot is specified as if it were a point lamp.
            : std::vector<std::pair<const char*, double>>{{"intensity", 1.0},
                                                          {"candela", 1.0 / kLumensPerWatt},
                                                          {"power", 0.25 / std::numbers::pi}};
    std::optional<At> strength_at;
    for (const auto& [key, factor] : strengths) {
      auto at = t.get(key);
      if (!at) continue;
      if (strength_at)
        at->fail("give one of its strengths, not both '" + strength_at->path + "' and '" +
                 at->path + "'");
      strength_at = at;
      const vec3 strength = read_colour(*at);  // one number, or one per channel
      if (glm::any(glm::lessThan(strength, vec3(0.0f)))) at->fail("must not be negative");
      lamp.intensity = colour * strength * float(factor);
    }
    if (!strength_at)
      t.at().fail(lamp.kind == LampKind::directional
                      ? "a directional light needs 'irradiance' (W/m^2) or 'lux'"
                      : "a " + type + " light needs 'power' (W), 'intensity' (W/sr) or 'candela'");
    if (lamp.kind != LampKind::directional) lamp.position = read_vector<3>(t.require("position"));
    if (auto range = t.get("range")) lamp.range = read_positive(*range);
    if (lamp.kind != LampKind::point) {
      auto direction = t.get("direction");
      auto target = lamp.kind == LampKind::spot ? t.get("target") : std::nullopt;
      if (direction && target) target->fail("give either 'direction' or 'target', not both");
      if (!direction && !target)
        t.at().fail("a " + type + " light needs 'direction'" +
                    (lamp.kind == LampKind::spot ? " or 'target'" : ""));
      const vec3 d =
          direction ? read_vector<3>(*direction) : read_vector<3>(*target) - lamp.position;
      if (!(glm::length(d) > 0.0f))
        (direction ? *direction : *target).fail("the light's direction has zero length");
      lamp.direction = glm::normalize(d);
    }
    if (lamp.kind == LampKind::spot) {
      float outer = 45.0f, inner = 0.0f;
      auto outer_at = t.get("outer_angle");
      if (outer_at) outer = read_number(*outer_at);
      if (auto inner_at = t.get("inner_angle")) inner = read_number(*inner_at);
      if (!(inner >= 0.0f && inner < outer && outer <= 90.0f))
        (outer_at ? *outer_at : t.at())
            .fail("spot angles need 0 <= inner_angle < outer_angle <= 90 degrees, got " +
                  format_number(inner) + " and " + format_number(outer));
      lamp.inner_cone = glm::radians(inner);
      lamp.outer_cone = glm::radians(outer);
    }
    result_.scene.lights.push_back(std::move(lamp));
  }

  // A light group's name (bake/light_groups.h): not empty, and no ',' or '=' (the separators
  // of --group-weights).
  static std::string read_group(const At& at) {
    const std::string name = read_string(at);
    if (name.empty() || name.find_first_of(",=") != std::string::npos)
      at.fail("a light group's name must be non-empty, without ',' or '=', got '" + name + "'");
    return name;
  }

  void build_sky(const TableAt& t) {
    t.warn_unknown_keys({"radiance", "image", "rotation", "group"}, "the sky", result_.warnings);
    Sky sky;
    if (auto group = t.get("group")) sky.light_group = read_group(*group);
    double degrees = 0.0;
    if (auto rotation = t.get("rotation")) {
      degrees = read_number(*rotation);
      if (!t.get("image")) rotation->fail("a sky's rotation turns its image: give 'image'");
      if (!std::isfinite(degrees) || std::abs(degrees) > 360.0)
        rotation->fail("sky rotation must be in [-360, 360] degrees");
    }
    if (auto image = t.get("image")) {
      sky.radiance = vec3(1.0f);  // the image alone sets the radiance unless both are given
      sky.texture = texture(*image, false, degrees);
    }
    if (auto radiance = t.get("radiance")) {
      sky.radiance = read_colour(*radiance);
      if (glm::any(glm::lessThan(sky.radiance, vec3(0.0f))))
        radiance->fail("sky radiance must not be negative");
    }
    if (!t.get("image") && !t.get("radiance"))
      t.at().fail("a sky needs 'radiance' (W/(sr m^2)) or 'image' (an equirect HDR file)");
    result_.scene.sky = sky;
  }

  struct PendingPower {
    vec3 watts;
    At at;
  };

  std::string top_path_;
  LoadResult result_;
  std::deque<toml::table> documents_;
  std::vector<LoadResult> gltf_includes_;  // included .gltf/.glb scenes, in include order  // owns every parsed file; the view points into them
  std::vector<std::string> include_chain_;
  std::map<std::string, TableAt> materials_;
  std::vector<std::string> material_order_;
  std::map<std::string, At> definitions_;
  std::map<std::string, uint64_t> placed_by_definition_;  // memo of objects_placed_by
  uint64_t objects_placed_ = 0;                           // shapes, mesh files and instances so far
  uint64_t triangles_placed_ = 0;
  std::vector<Named> objects_;
  std::vector<Named> cameras_;
  std::vector<Named> lights_;
  std::optional<TableAt> sky_;
  std::map<std::string, int> material_index_;
  std::vector<std::optional<PendingPower>> material_power_;  // per scene material
  std::map<std::tuple<std::string, bool, double>, int> texture_index_;
  std::map<std::string, Mesh> mesh_file_cache_;
  int default_material_ = -1;
  std::vector<std::string> mesh_places_;  // per scene mesh: "FILE:LINE:COL: objects[i]"
};

}  // namespace

LoadResult load_scene_toml(const std::string& path) {
  return TomlSceneLoader(path).load();
}

}  // namespace lb
