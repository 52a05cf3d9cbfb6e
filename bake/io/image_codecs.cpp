// The image calls of image_codecs.h, forwarded to lightbake_images.so (image_plugin.h), which is
// opened on the first of them: from LIGHTBAKE_PLUGIN_FROM_BINDIR (../lib/lightbake) relative to
// the lightbake executable, installed or in the build tree; other executables (tests) find it
// in the build tree that made them, else by name through their run path (CMakeLists.txt).

#include "bake/io/image_codecs.h"

#include <dlfcn.h>

#include <cfenv>

#include <filesystem>
#include <stdexcept>

#include "bake/io/image_plugin.h"

namespace lb::codecs {

namespace {

// The plugin at its place relative to the running executable, else in the build tree that
// made this binary (tests, benchmarks: their run path also names it, but AddressSanitizer's
// dlopen interceptor searches libasan's run path instead); "" when neither has it.
std::string installed_plugin() {
  namespace fs = std::filesystem;
  std::error_code error;
  const fs::path executable = fs::read_symlink("/proc/self/exe", error);
  if (!error) {
    const fs::path place = executable.parent_path() / LIGHTBAKE_PLUGIN_FROM_BINDIR;
    const fs::path plugin = (place / kImagePluginFile).lexically_normal();
    if (fs::is_regular_file(plugin, error)) return plugin.string();
  }
  const fs::path built = fs::path(LIGHTBAKE_BUILD_PLUGIN_DIR) / kImagePluginFile;
  return fs::is_regular_file(built, error) ? built.string() : "";
}

const ImagePlugin* open_plugin() {
  const std::string installed = installed_plugin();
  // A library built with -ffast-math sets flush-to-zero in the loading thread from its
  // constructor; OpenImageIO pulls in hundreds. The floating-point environment is put back, so
  // a bake after the first image read has the bits of one before it.
  std::fenv_t environment;
  std::fegetenv(&environment);
  void* library = ::dlopen(installed.empty() ? kImagePluginFile : installed.c_str(),
                           RTLD_NOW | RTLD_LOCAL);
  std::fesetenv(&environment);
  if (!library)
    throw std::runtime_error(std::string("cannot load the image library: ") + ::dlerror());
  // Never closed: OpenImageIO keeps threads and caches for the life of the process.
  const auto entry = reinterpret_cast<ImagePluginEntry>(::dlsym(library, kImagePluginEntry));
  if (!entry)
    throw std::runtime_error(std::string("cannot load the image library: ") + ::dlerror());
  const ImagePlugin* plugin = entry(kImagePluginVersion);
  if (!plugin)
    throw std::runtime_error(std::string("cannot load the image library: ") + kImagePluginFile +
                             " is from another build of lightbake");
  return plugin;
}

// Opened once; a failure is thrown to each caller that asks until one succeeds.
const ImagePlugin& plugin() {
  static const ImagePlugin* const loaded = open_plugin();
  return *loaded;
}

}  // namespace

Decoded decode(const Source& source, int max_channels, uint64_t max_values) {
  Decoded decoded;
  std::string problem;
  try {
    problem = plugin().decode(source, max_channels, max_values, decoded);
  } catch (const std::runtime_error& error) {
    problem = error.what();
  }
  if (!problem.empty()) throw CodecError(problem);
  return decoded;
}

std::vector<unsigned char> encode(const std::string& format, const Pixels& pixels) {
  std::vector<unsigned char> bytes;
  const std::string problem = plugin().encode(format, pixels, bytes);
  if (!problem.empty()) throw std::runtime_error(problem);
  return bytes;
}

bool is_stamped(const std::string& path) {
  return plugin().software(path) == kSoftware;
}

}  // namespace lb::codecs
