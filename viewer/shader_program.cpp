#include "viewer/shader_program.h"

#include <fstream>
#include <glm/gtc/type_ptr.hpp>
#include <set>
#include <sstream>
#include <stdexcept>

#include "viewer/embedded_shaders.h"

namespace lb {

namespace {

std::string read_text(const std::string& directory, const std::string& file) {
  if (directory.empty()) {
    for (const EmbeddedShader& shader : embedded_shaders())
      if (shader.file == file) return std::string(shader.text);
    throw std::runtime_error(shader_path(directory, file) + ": no such built-in shader");
  }
  const std::string path = shader_path(directory, file);
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open shader source");
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

void append_resolved(const std::string& directory, const std::string& file,
                     std::set<std::string>& included, std::string& out) {
  if (!included.insert(file).second) return;
  std::istringstream lines(read_text(directory, file));
  std::string line;
  int number = 0;
  while (std::getline(lines, line)) {
    ++number;
    const auto start = line.find_first_not_of(" \t");
    if (start != std::string::npos && line.compare(start, 8, "#include") == 0) {
      const auto open = line.find('"', start);
      const auto close = open == std::string::npos ? open : line.find('"', open + 1);
      if (close == std::string::npos) {
        throw std::runtime_error(shader_path(directory, file) + ":" + std::to_string(number) +
                                 ": malformed #include");
      }
      append_resolved(directory, line.substr(open + 1, close - open - 1), included, out);
      continue;
    }
    out += line;
    out += '\n';
  }
}

GLuint compile(GLenum stage, const std::string& source, const std::string& name) {
  const GLuint shader = glCreateShader(stage);
  const char* text = source.c_str();
  glShaderSource(shader, 1, &text, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    GLint length = 0;
    glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
    std::string log(size_t(std::max(length, 1)), '\0');
    glGetShaderInfoLog(shader, length, nullptr, log.data());
    glDeleteShader(shader);
    throw std::runtime_error(name + ": shader compile failed: " + log);
  }
  return shader;
}

}  // namespace

std::string default_shader_directory() {
  return {};
}

std::string shader_path(const std::string& directory, const std::string& file) {
  return directory.empty() ? "built-in:" + file : directory + "/" + file;
}

std::string assemble_shader(const std::string& directory, const std::string& file,
                            const std::vector<std::string>& defines) {
  std::string out = "#version 330 core\n";
  for (const auto& define : defines) out += "#define " + define + "\n";
  std::set<std::string> included;
  append_resolved(directory, file, included, out);
  return out;
}

ShaderProgram ShaderProgram::build(const std::string& directory, const std::string& vertex_file,
                                   const std::string& fragment_file,
                                   const std::vector<std::string>& defines) {
  const std::string vertex_name = shader_path(directory, vertex_file);
  const std::string fragment_name = shader_path(directory, fragment_file);
  const GLuint vertex =
      compile(GL_VERTEX_SHADER, assemble_shader(directory, vertex_file, defines), vertex_name);
  GLuint fragment = 0;
  try {
    fragment = compile(GL_FRAGMENT_SHADER, assemble_shader(directory, fragment_file, defines),
                       fragment_name);
  } catch (...) {
    glDeleteShader(vertex);
    throw;
  }
  ShaderProgram result;
  result.program_ = gl::Program(glCreateProgram());
  const GLuint program = result.program_.get();
  glAttachShader(program, vertex);
  glAttachShader(program, fragment);
  glLinkProgram(program);
  glDeleteShader(vertex);
  glDeleteShader(fragment);
  GLint ok = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) {
    GLint length = 0;
    glGetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
    std::string log(size_t(std::max(length, 1)), '\0');
    glGetProgramInfoLog(program, length, nullptr, log.data());
    throw std::runtime_error(vertex_name + " + " + fragment_name + ": link failed: " + log);
  }
  return result;
}

GLint ShaderProgram::location(const char* name) const {
  auto it = locations_.find(name);
  if (it != locations_.end()) return it->second;
  const GLint loc = glGetUniformLocation(program_.get(), name);
  locations_.emplace(name, loc);
  return loc;
}

void ShaderProgram::set(const char* name, glm::vec3 value) const {
  glUniform3fv(location(name), 1, glm::value_ptr(value));
}

void ShaderProgram::set(const char* name, const glm::mat4& value) const {
  glUniformMatrix4fv(location(name), 1, GL_FALSE, glm::value_ptr(value));
}

}  // namespace lb
