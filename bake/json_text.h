#pragma once
// JSON text for files and stdout. Strings from the file system (scene and output paths, file
// and mesh names) are bytes that need not be UTF-8, and nlohmann's dump() throws on those after
// all the work is done; here each invalid byte becomes U+FFFD, so the result is still written.

#include <nlohmann/json.hpp>
#include <string>

namespace lb {

// json.dump(indent), with bytes that are not UTF-8 replaced by U+FFFD.
inline std::string json_text(const nlohmann::json& json, int indent = -1) {
  return json.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace);
}

// `text` with the same replacement, for libraries that serialise strings themselves (tinygltf).
inline std::string valid_utf8(const std::string& text) {
  return nlohmann::json::parse(json_text(nlohmann::json(text))).get<std::string>();
}

}  // namespace lb
