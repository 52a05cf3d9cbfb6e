#pragma once
// Shader programs assembled from chunks under shaders/: `#include "chunk.glsl"` lines are
// replaced by the chunk (each once), and `#version 330 core` plus the given defines are put
// in front. The chunks come from the copies built into the binary (viewer/embedded_shaders.h)
// or, for shader development, from a directory. Compile and link errors throw with the file
// name and the driver's log.

#include <glm/glm.hpp>
#include <string>
#include <unordered_map>
#include <vector>

#include "viewer/gl_resources.h"

namespace lb {

// The default shader directory: empty, meaning the shaders built into the binary.
std::string default_shader_directory();

// Where `file` is read from, for messages: DIRECTORY/FILE, or "built-in:FILE".
std::string shader_path(const std::string& directory, const std::string& file);

// The full source of `file` with includes resolved and the header in front; `directory`
// empty reads the built-in copies.
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
  void set(const char* name, const float* values, int count) const {
    glUniform1fv(location(name), count, values);
  }
  void set(const char* name, const glm::vec3* values, int count) const {
    glUniform3fv(location(name), count, &values[0].x);
  }
  explicit operator bool() const { return bool(program_); }

 private:
  gl::Program program_;
  mutable std::unordered_map<std::string, GLint> locations_;
};

}  // namespace lb
