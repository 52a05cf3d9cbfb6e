#pragma once
// Shader programs assembled from chunks under shaders/: `#include "chunk.glsl"` lines are
// replaced by the chunk (each once), and `#version 330 core` plus the given defines are put
// in front. Compile and link errors throw with the file name and the driver's log.

#include <glm/glm.hpp>
#include <string>
#include <unordered_map>
#include <vector>

#include "viewer/gl_resources.h"

namespace lb {

// The directory the shaders were built from (a compile definition), for the default.
std::string default_shader_directory();

// The full source of `file` with includes resolved and the header in front.
std::string assemble_shader(const std::string& directory, const std::string& file,
                            const std::vector<std::string>& defines);

class ShaderProgram {
 public:
  ShaderProgram() = default;
  static ShaderProgram build(const std::string& directory, const std::string& vertex_file,
                             const std::string& fragment_file,
                             const std::vector<std::string>& defines = {});

  void use() const { glUseProgram(program_.get()); }
  GLint location(const char* name) const;  // -1 when the uniform is unused (that is fine)
  void set(const char* name, int value) const { glUniform1i(location(name), value); }
  void set(const char* name, float value) const { glUniform1f(location(name), value); }
  void set(const char* name, glm::vec3 value) const;
  void set(const char* name, const glm::mat4& value) const;
  explicit operator bool() const { return bool(program_); }

 private:
  gl::Program program_;
  mutable std::unordered_map<std::string, GLint> locations_;
};

}  // namespace lb
