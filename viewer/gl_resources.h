#pragma once
// Move-only owners of OpenGL objects, so a failed upload or a scene change never leaks.
// All of them need the context that created them to be current when they die.

#include <string>
#include <utility>

#include "viewer/gl.h"

namespace lb::gl {

template <void (*Delete)(GLuint)>
class Handle {
 public:
  Handle() = default;
  explicit Handle(GLuint id) : id_(id) {}
  ~Handle() { reset(); }
  Handle(Handle&& other) noexcept : id_(std::exchange(other.id_, 0)) {}
  Handle& operator=(Handle&& other) noexcept {
    if (this != &other) {
      reset();
      id_ = std::exchange(other.id_, 0);
    }
    return *this;
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  GLuint get() const { return id_; }
  explicit operator bool() const { return id_ != 0; }
  void reset() {
    if (id_) Delete(id_);
    id_ = 0;
  }

 private:
  GLuint id_ = 0;
};

void delete_buffer(GLuint id);
void delete_texture(GLuint id);
void delete_vertex_array(GLuint id);
void delete_framebuffer(GLuint id);
void delete_program(GLuint id);

using Buffer = Handle<delete_buffer>;
using Texture = Handle<delete_texture>;
using VertexArray = Handle<delete_vertex_array>;
using Framebuffer = Handle<delete_framebuffer>;
using Program = Handle<delete_program>;

Buffer make_buffer();
Texture make_texture();
VertexArray make_vertex_array();
Framebuffer make_framebuffer();

// A buffer texture (samplerBuffer) over `bytes` of data in `format` (e.g. GL_RGB32F).
struct BufferTexture {
  Buffer buffer;
  Texture texture;
};
BufferTexture make_buffer_texture(GLenum format, const void* data, size_t bytes);

// Throws std::runtime_error naming `where` if GL reported an error since the last check.
void check_errors(const std::string& where);

}  // namespace lb::gl
