#pragma once
// The shaders of shaders/ compiled into the binary (cmake/EmbedShaders.cmake generates the
// definition), so an installed lightbake runs without the source tree.

#include <span>
#include <string_view>

namespace lb {

struct EmbeddedShader {
  std::string_view file;  // name under shaders/, e.g. "scene.frag"
  std::string_view text;  // the file's bytes as they were at build time
};

// Every embedded shader, sorted by file name.
std::span<const EmbeddedShader> embedded_shaders();

}  // namespace lb
