#pragma once
// Checks on a glTF's JSON text made before tinygltf parses it: nesting depth (tinygltf
// converts JSON recursively and would overflow the stack), the version, the scene index,
// camera projections, empty meshes and where buffer and image URIs point. tinygltf accepts all
// of these silently.

#include <string>
#include <string_view>

namespace lb {

// Byte offset of the first bracket nested deeper than `max_depth` ([ and { outside strings),
// or std::string_view::npos.
size_t json_too_deep_at(std::string_view json, int max_depth);

// Throws SceneError "PATH: at KEY.PATH: message" (or "PATH: at byte N: ...") for the problems
// above. `path` is the .gltf or .glb; `json` its JSON text (for a .glb, the JSON chunk, which
// starts at byte `json_offset` of the file). URIs must resolve inside the file's folder unless
// `allow_outside_uris`; data: URIs always pass.
void precheck_gltf_json(const std::string& path, std::string_view json, size_t json_offset,
                        bool allow_outside_uris);

}  // namespace lb
