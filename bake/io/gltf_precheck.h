#pragma once
// Checks on a glTF's JSON text made before tinygltf parses it: nesting depth (tinygltf
// converts JSON recursively and would overflow the stack), the version, the scene index,
// camera projections, empty meshes and where buffer and image URIs point (tinygltf accepts all
// of these silently); animations are cut out and extensions listed.

#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace lb {

// Byte offset of the first bracket nested deeper than `max_depth` ([ and { outside strings),
// or std::string_view::npos.
size_t json_too_deep_at(std::string_view json, int max_depth);

// What the precheck found that the loader reports or works around.
struct GltfJsonSummary {
  // `animations` had this many entries. They and `skins` are cut from the JSON before tinygltf
  // parses it: tinygltf refuses animation channels without `target.node`, which is how
  // KHR_animation_pointer (as Blender 4 writes it) animates, and skins without the optional
  // `inverseBindMatrices`; the loader shows the scene at rest in its bind pose anyway.
  size_t animations = 0;
  // The JSON text to parse when it differs from the file's (animations or skins cut), else
  // empty.
  std::string stripped_json;
  // Every extension named in an `extensions` object outside `animations`, with the first JSON
  // path where it appears ("materials[0].extensions.KHR_materials_sheen"; keys are walked in
  // alphabetical order, so "first" means first in that order).
  std::vector<std::pair<std::string, std::string>> extensions;
};

// Throws SceneError "PATH: at KEY.PATH: message" (or "PATH: at byte N: ...") for the problems
// above. `path` is the .gltf or .glb; `json` its JSON text (for a .glb, the JSON chunk, which
// starts at byte `json_offset` of the file). URIs must resolve inside the file's folder unless
// `allow_outside_uris`; data: URIs always pass.
GltfJsonSummary precheck_gltf_json(const std::string& path, std::string_view json,
                                   size_t json_offset, bool allow_outside_uris);

}  // namespace lb
