#include "bake/io/gltf_precheck.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>

#include "bake/io/input_limits.h"
#include "bake/io/scene_load.h"

namespace lb {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

[[noreturn]] void fail(const std::string& path, const std::string& place,
                       const std::string& message) {
  throw SceneError(path + ": at " + place + ": " + message);
}

// "%2e%2E/x" -> "../x": tinygltf decodes URIs the same way before opening them.
std::string percent_decoded(const std::string& uri) {
  std::string out;
  for (size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '%' && i + 2 < uri.size() &&
        std::isxdigit(static_cast<unsigned char>(uri[i + 1])) &&
        std::isxdigit(static_cast<unsigned char>(uri[i + 2]))) {
      out += char(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else {
      out += uri[i];
    }
  }
  return out;
}

// True when `inner` is `outer` or below it (both canonical).
bool is_within(const fs::path& inner, const fs::path& outer) {
  auto i = inner.begin();
  for (auto o = outer.begin(); o != outer.end(); ++o, ++i)
    if (i == inner.end() || *i != *o) return false;
  return true;
}

void check_uri(const std::string& path, const json& object, const std::string& place) {
  if (!object.is_object() || !object.contains("uri") || !object["uri"].is_string()) return;
  const std::string uri = object["uri"].get<std::string>();
  if (uri.rfind("data:", 0) == 0) return;
  const std::string decoded = percent_decoded(uri);
  const bool has_scheme = decoded.find("://") != std::string::npos;
  const fs::path relative(decoded);
  if (has_scheme || relative.is_absolute() || relative.has_root_name())
    fail(path, place + ".uri",
         "'" + uri +
             "' is absolute; only files in the scene's folder are read "
             "(--allow-outside-uris reads it anyway)");
  std::error_code error;
  const fs::path folder = fs::weakly_canonical(fs::absolute(path).parent_path(), error);
  const fs::path target = fs::weakly_canonical(folder / relative, error);
  if (error || !is_within(target, folder))
    fail(path, place + ".uri",
         "'" + uri + "' points outside the scene's folder " + folder.string() +
             " (--allow-outside-uris reads it anyway)");
}

// An external file must be a regular one: tinygltf would block opening a FIFO, or read a
// device forever. A missing file is tinygltf's to report.
void check_uri_file(const std::string& path, const json& object, const std::string& place) {
  if (!object.is_object() || !object.contains("uri") || !object["uri"].is_string()) return;
  const std::string uri = object["uri"].get<std::string>();
  if (uri.rfind("data:", 0) == 0) return;
  const fs::path file = fs::absolute(path).parent_path() / fs::path(percent_decoded(uri));
  const std::string problem = input_file_problem(file.string());
  if (!problem.empty() && problem != "does not exist")
    fail(path, place + ".uri", "'" + uri + "' " + problem);
}

void check_cameras(const std::string& path, const json& cameras) {
  for (size_t i = 0; i < cameras.size(); ++i) {
    const json& camera = cameras[i];
    if (!camera.is_object() || !camera.contains("perspective")) continue;
    const json& p = camera["perspective"];
    if (!p.is_object()) continue;
    const std::string place = "cameras[" + std::to_string(i) + "].perspective.";
    auto number = [&](const char* key) -> std::optional<double> {
      if (!p.contains(key) || !p[key].is_number()) return std::nullopt;
      return p[key].get<double>();
    };
    const auto aspect = number("aspectRatio");
    if (aspect && !(*aspect > 0.0))
      fail(path, place + "aspectRatio", "must be positive, got " + p["aspectRatio"].dump());
    const auto znear = number("znear");
    if (znear && !(*znear > 0.0))
      fail(path, place + "znear", "must be positive, got " + p["znear"].dump());
    const auto zfar = number("zfar");
    if (zfar && !(*zfar > znear.value_or(0.0)))
      fail(path, place + "zfar", "must exceed znear, got " + p["zfar"].dump());
  }
}

// Depth-first over the JSON tree (depth is bounded by kMaxJsonDepth, checked first): the first
// place each extension name appears in an `extensions` object.
void list_extensions(const json& node, const std::string& place,
                     std::vector<std::pair<std::string, std::string>>& found) {
  if (node.is_object()) {
    for (const auto& [key, value] : node.items()) {
      const std::string child = place.empty() ? key : place + "." + key;
      if (key == "extensions" && value.is_object())
        for (const auto& [name, unused] : value.items()) {
          (void)unused;
          const bool seen = std::any_of(found.begin(), found.end(),
                                        [&](const auto& entry) { return entry.first == name; });
          if (!seen) found.emplace_back(name, child + "." + name);
        }
      list_extensions(value, child, found);
    }
  } else if (node.is_array()) {
    for (size_t i = 0; i < node.size(); ++i)
      if (node[i].is_structured())  // no place strings for the numbers of a long array
        list_extensions(node[i], place + "[" + std::to_string(i) + "]", found);
  }
}

}  // namespace

size_t json_too_deep_at(std::string_view text, int max_depth) {
  int depth = 0;
  bool in_string = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\')
        ++i;  // the escaped character cannot end the string
      else if (c == '"')
        in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > max_depth) return i;
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return std::string_view::npos;
}

GltfJsonSummary precheck_gltf_json(const std::string& path, std::string_view text,
                                   size_t json_offset, bool allow_outside_uris) {
  if (const size_t at = json_too_deep_at(text, limits::kMaxJsonDepth); at != std::string_view::npos)
    fail(path, "byte " + std::to_string(json_offset + at),
         "JSON nested deeper than " + std::to_string(limits::kMaxJsonDepth) + " levels");
  GltfJsonSummary summary;
  json root = json::parse(text, nullptr, false);
  if (root.is_discarded() || !root.is_object()) return summary;  // tinygltf reports the error

  if (root.contains("asset") && root["asset"].is_object() && root["asset"].contains("version")) {
    const json& version = root["asset"]["version"];
    const std::string text_version =
        version.is_string() ? version.get<std::string>() : version.dump();
    if (text_version.rfind("2.", 0) != 0)
      fail(path, "asset.version",
           "glTF " + text_version + " is not supported (only glTF 2.0 is read)");
  }
  if (root.contains("scene") &&
      !(root["scene"].is_number_integer() && root["scene"].get<long long>() >= 0))
    fail(path, "scene", root["scene"].dump() + " is not a scene index");
  if (root.contains("meshes") && root["meshes"].is_array()) {
    const json& meshes = root["meshes"];
    for (size_t i = 0; i < meshes.size(); ++i)
      if (meshes[i].is_object() && meshes[i].contains("primitives") &&
          meshes[i]["primitives"].is_array() && meshes[i]["primitives"].empty())
        fail(path, "meshes[" + std::to_string(i) + "].primitives",
             "empty; a mesh needs at least one primitive");
  }
  if (root.contains("cameras") && root["cameras"].is_array()) check_cameras(path, root["cameras"]);
  for (const char* list : {"buffers", "images"}) {
    if (!root.contains(list) || !root[list].is_array()) continue;
    const json& items = root[list];
    for (size_t i = 0; i < items.size(); ++i) {
      const std::string place = std::string(list) + "[" + std::to_string(i) + "]";
      if (!allow_outside_uris) check_uri(path, items[i], place);
      check_uri_file(path, items[i], place);
    }
  }
  // Cut what the loader ignores and tinygltf may refuse: animation channels without
  // target.node (KHR_animation_pointer), skins without inverseBindMatrices (optional in glTF).
  bool cut = false;
  for (const char* ignored : {"animations", "skins"}) {
    if (!root.contains(ignored)) continue;
    if (std::string(ignored) == "animations")
      summary.animations = root[ignored].is_array() ? root[ignored].size() : 1;
    root.erase(ignored);
    cut = true;
  }
  if (cut) summary.stripped_json = root.dump();
  list_extensions(root, "", summary.extensions);
  return summary;
}

}  // namespace lb
