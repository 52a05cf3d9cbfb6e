#include "viewer/gl_resources.h"

#include <cstdio>
#include <stdexcept>

namespace lb::gl {

void delete_buffer(GLuint id) {
  glDeleteBuffers(1, &id);
}
void delete_texture(GLuint id) {
  glDeleteTextures(1, &id);
}
void delete_vertex_array(GLuint id) {
  glDeleteVertexArrays(1, &id);
}
void delete_framebuffer(GLuint id) {
  glDeleteFramebuffers(1, &id);
}
void delete_program(GLuint id) {
  glDeleteProgram(id);
}

Buffer make_buffer() {
  GLuint id = 0;
  glGenBuffers(1, &id);
  return Buffer(id);
}
Texture make_texture() {
  GLuint id = 0;
  glGenTextures(1, &id);
  return Texture(id);
}
VertexArray make_vertex_array() {
  GLuint id = 0;
  glGenVertexArrays(1, &id);
  return VertexArray(id);
}
Framebuffer make_framebuffer() {
  GLuint id = 0;
  glGenFramebuffers(1, &id);
  return Framebuffer(id);
}

BufferTexture make_buffer_texture(GLenum format, const void* data, size_t bytes) {
  BufferTexture result{make_buffer(), make_texture()};
  glBindBuffer(GL_TEXTURE_BUFFER, result.buffer.get());
  // An empty buffer texture is legal but some drivers dislike size 0: keep one element.
  static const float zeros[4] = {0, 0, 0, 0};
  glBufferData(GL_TEXTURE_BUFFER, GLsizeiptr(bytes > 0 ? bytes : sizeof(zeros)),
               bytes > 0 ? data : zeros, GL_STATIC_DRAW);
  glBindTexture(GL_TEXTURE_BUFFER, result.texture.get());
  glTexBuffer(GL_TEXTURE_BUFFER, format, result.buffer.get());
  glBindTexture(GL_TEXTURE_BUFFER, 0);
  glBindBuffer(GL_TEXTURE_BUFFER, 0);
  return result;
}

void check_errors(const std::string& where) {
  const GLenum error = glGetError();
  if (error == GL_NO_ERROR) return;
  while (glGetError() != GL_NO_ERROR) {
  }
  throw std::runtime_error(where + ": OpenGL error 0x" + [&] {
    char text[16];
    std::snprintf(text, sizeof(text), "%04x", unsigned(error));
    return std::string(text);
  }());
}

}  // namespace lb::gl
