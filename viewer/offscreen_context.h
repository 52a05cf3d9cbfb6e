#pragma once
// An OpenGL 3.3 core context without a window (Mesa's OSMesa, software rendering), current
// on the creating thread for the object's lifetime, with GL loaded. The renderer draws into
// its own framebuffers, so the OSMesa buffer itself is tiny.

#include <memory>

namespace lb {

class OffscreenContext {
 public:
  OffscreenContext();  // throws std::runtime_error when no core context can be made
  ~OffscreenContext();
  OffscreenContext(const OffscreenContext&) = delete;
  OffscreenContext& operator=(const OffscreenContext&) = delete;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace lb
