#pragma once
// Loading scenes: the native TOML format (scene_toml.cpp) and glTF 2.0 (scene_gltf.cpp).
// Every problem is reported with the file and the place (line:column or a key path).

#include <stdexcept>
#include <string>
#include <vector>

#include "bake/input_file.h"
#include "bake/scene.h"

namespace lb {

// A fatal problem with the input. what() reads "FILE:LINE:COL: message" or
// "FILE: at KEY.PATH: message": one line, ready to print.
struct SceneError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The first line of a library's error text, trailing whitespace removed: what a one-line
// SceneError quotes as the reason.
std::string first_line(const std::string& text);

struct LoadResult {
  Scene scene;
  std::vector<std::string> warnings;  // each one line, naming the file and place
};

struct SceneLoadOptions {
  // glTF buffer and image URIs may point outside the scene file's folder (absolute paths, `..`).
  // Off by default: a downloaded scene must not read /etc/passwd or ~/.ssh into a texture.
  bool allow_outside_uris = false;
  // The file is an include of a TOML scene: the light it lacks may come from the including
  // file (a [sky], lamps), so "nothing emits light" is left to the whole scene's check.
  bool included = false;
};

// Chooses the loader by extension: .toml -> native, .gltf/.glb -> glTF.
LoadResult load_scene(const std::string& path, const SceneLoadOptions& options = {});

LoadResult load_scene_toml(const std::string& path);
LoadResult load_scene_gltf(const std::string& path, const SceneLoadOptions& options = {});

// Checks the invariants every pass relies on (indices in range, finite coordinates, unit
// normals, reflectance in [0,1], ...) and cleans what can be cleaned: degenerate and
// zero-area triangles are dropped with a warning that counts them. Throws SceneError.
void validate_scene(Scene& scene, std::vector<std::string>& warnings);

}  // namespace lb
