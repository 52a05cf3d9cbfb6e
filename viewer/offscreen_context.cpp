#include "viewer/offscreen_context.h"

#include <stdexcept>
#include <vector>

// clang-format off
#include "viewer/renderer.h"  // load_gl; includes glad before osmesa.h pulls in GL/gl.h
#include <GL/osmesa.h>
// clang-format on

namespace lb {

struct OffscreenContext::Impl {
  OSMesaContext context = nullptr;
  std::vector<unsigned char> buffer = std::vector<unsigned char>(4 * 4 * 4);
};

OffscreenContext::OffscreenContext() : impl_(std::make_unique<Impl>()) {
  // Try 4.5 core first (what llvmpipe offers), then 3.3 core.
  for (int minor_major : {45, 33}) {
    const int attributes[] = {OSMESA_FORMAT,
                              OSMESA_RGBA,
                              OSMESA_DEPTH_BITS,
                              24,
                              OSMESA_PROFILE,
                              OSMESA_CORE_PROFILE,
                              OSMESA_CONTEXT_MAJOR_VERSION,
                              minor_major / 10,
                              OSMESA_CONTEXT_MINOR_VERSION,
                              minor_major % 10,
                              0};
    impl_->context = OSMesaCreateContextAttribs(attributes, nullptr);
    if (impl_->context) break;
  }
  if (!impl_->context) throw std::runtime_error("OSMesa: cannot create an OpenGL core context");
  if (!OSMesaMakeCurrent(impl_->context, impl_->buffer.data(), GL_UNSIGNED_BYTE, 4, 4)) {
    OSMesaDestroyContext(impl_->context);
    throw std::runtime_error("OSMesa: cannot make the context current");
  }
  load_gl(reinterpret_cast<GlProcLoader>(OSMesaGetProcAddress));
}

OffscreenContext::~OffscreenContext() {
  OSMesaMakeCurrent(nullptr, nullptr, GL_UNSIGNED_BYTE, 0, 0);
  OSMesaDestroyContext(impl_->context);
}

}  // namespace lb
