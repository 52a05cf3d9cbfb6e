#include "bake/lightmap/oidn.h"

#include <dlfcn.h>

#include <cfenv>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <stdexcept>

namespace lb {

namespace {

// OIDN 2's C API (include/OpenImageDenoise/oidn.h), the calls used here: handles are opaque
// pointers, enums ints.
using OidnDevice = void*;
using OidnFilter = void*;
constexpr int kDeviceTypeCpu = 1;   // OIDN_DEVICE_TYPE_CPU
constexpr int kFormatFloat3 = 3;    // OIDN_FORMAT_FLOAT3
constexpr int kErrorNone = 0;       // OIDN_ERROR_NONE
constexpr const char* kLibraryName = "libOpenImageDenoise.so.2";

struct OidnApi {
  std::string path;
  OidnDevice (*new_device)(int);
  void (*set_device_bool)(OidnDevice, const char*, bool);
  void (*commit_device)(OidnDevice);
  int (*get_device_error)(OidnDevice, const char**);
  OidnFilter (*new_filter)(OidnDevice, const char*);
  void (*set_shared_filter_image)(OidnFilter, const char*, void*, int, size_t, size_t, size_t,
                                  size_t, size_t);
  void (*set_filter_bool)(OidnFilter, const char*, bool);
  void (*commit_filter)(OidnFilter);
  void (*execute_filter)(OidnFilter);
  void (*release_filter)(OidnFilter);
  OidnDevice device = nullptr;
};

const char* const kHowToGet =
    "--denoise needs Intel Open Image Denoise: set LIGHTBAKE_OIDN_LIB to its "
    "libOpenImageDenoise.so.2 (pip install --target DIR pyoidn: DIR/pyoidn/oidn/lib/)";

// $LIGHTBAKE_OIDN_LIB, else the build tree's copy, else the bare name for the loader's path.
std::string library_to_open() {
  namespace fs = std::filesystem;
  std::error_code error;
  if (const char* given = std::getenv("LIGHTBAKE_OIDN_LIB"); given && *given) {
    if (!fs::is_regular_file(given, error))
      throw std::runtime_error(std::string(kHowToGet) + "; LIGHTBAKE_OIDN_LIB=" + given +
                               " is not a file");
    return given;
  }
  if (fs::is_regular_file(LIGHTBAKE_BUILD_OIDN_LIB, error)) return LIGHTBAKE_BUILD_OIDN_LIB;
  return kLibraryName;
}

template <typename F>
void bind(void* library, const char* name, F& function) {
  function = reinterpret_cast<F>(::dlsym(library, name));
  if (!function)
    throw std::runtime_error(std::string(kHowToGet) + "; its library lacks " + name);
}

OidnApi open_oidn() {
  OidnApi api;
  api.path = library_to_open();
  // Like the image plugin (image_codecs.cpp): a library's constructors may change the
  // floating-point environment; it is put back so later bakes keep their bits.
  std::fenv_t environment;
  std::fegetenv(&environment);
  void* library = ::dlopen(api.path.c_str(), RTLD_NOW | RTLD_LOCAL);
  std::fesetenv(&environment);
  if (!library) throw std::runtime_error(std::string(kHowToGet) + " (" + ::dlerror() + ")");
  // Never closed: the device keeps TBB's arena for the life of the process.
  bind(library, "oidnNewDevice", api.new_device);
  bind(library, "oidnSetDeviceBool", api.set_device_bool);
  bind(library, "oidnCommitDevice", api.commit_device);
  bind(library, "oidnGetDeviceError", api.get_device_error);
  bind(library, "oidnNewFilter", api.new_filter);
  bind(library, "oidnSetSharedFilterImage", api.set_shared_filter_image);
  bind(library, "oidnSetFilterBool", api.set_filter_bool);
  bind(library, "oidnCommitFilter", api.commit_filter);
  bind(library, "oidnExecuteFilter", api.execute_filter);
  bind(library, "oidnReleaseFilter", api.release_filter);
  api.device = api.new_device(kDeviceTypeCpu);
  if (api.device) {
    // No thread pinning: it makes TBB load libtbbbind with RTLD_DEEPBIND, which
    // AddressSanitizer refuses (the sanitizer suite), and the bake's threads are TBB's too.
    api.set_device_bool(api.device, "setAffinity", false);
    api.commit_device(api.device);
  }
  const char* message = nullptr;
  if (!api.device || api.get_device_error(api.device, &message) != kErrorNone)
    throw std::runtime_error(std::string("Open Image Denoise (") + api.path +
                             "): no CPU device: " + (message ? message : "unknown error"));
  return api;
}

std::mutex oidn_mutex;  // one filter at a time on the one device

// Opened once; a failure is thrown to each caller that asks until one succeeds.
const OidnApi& oidn() {
  static const OidnApi api = open_oidn();
  return api;
}

}  // namespace

std::string require_oidn() {
  const std::lock_guard<std::mutex> lock(oidn_mutex);
  return oidn().path;
}

std::vector<vec3> oidn_denoise(int width, int height, const std::vector<vec3>& color) {
  if (width <= 0 || height <= 0 || color.size() != size_t(width) * size_t(height))
    throw std::invalid_argument("oidn_denoise: the image is not width x height");
  const std::lock_guard<std::mutex> lock(oidn_mutex);
  const OidnApi& api = oidn();
  std::vector<vec3> input = color, output(color.size(), vec3(0.0f));
  const OidnFilter filter = api.new_filter(api.device, "RT");
  std::fenv_t environment;
  std::fegetenv(&environment);
  if (filter) {
    api.set_shared_filter_image(filter, "color", input.data(), kFormatFloat3, size_t(width),
                                size_t(height), 0, sizeof(vec3), 0);
    api.set_shared_filter_image(filter, "output", output.data(), kFormatFloat3, size_t(width),
                                size_t(height), 0, sizeof(vec3), 0);
    api.set_filter_bool(filter, "hdr", true);
    api.commit_filter(filter);
    api.execute_filter(filter);
    api.release_filter(filter);
  }
  std::fesetenv(&environment);
  const char* message = nullptr;
  if (!filter || api.get_device_error(api.device, &message) != kErrorNone)
    throw std::runtime_error(std::string("Open Image Denoise: ") +
                             (message ? message : "unknown error"));
  return output;
}

}  // namespace lb
