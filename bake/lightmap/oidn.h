#pragma once
// Intel Open Image Denoise (OIDN 2), the reference denoiser of rendering, opened with dlopen on
// first use: Debian has no package, the PyPI wheel `pyoidn` ships its library (no headers), so
// the handful of C calls used are declared in oidn.cpp. Found at $LIGHTBAKE_OIDN_LIB (the path
// of libOpenImageDenoise.so.2), else in the build tree's PyPI folder (scripts/test.sh runs
// `pip install --target build/pypi pyoidn`), else by name on the loader's path. Its CPU device
// runs on the process's TBB (Debian's libtbb.so.12, already loaded for Embree, has every symbol
// it needs), so `--threads` limits it too, unpinned (oidn.cpp: pinning breaks AddressSanitizer).

#include <string>
#include <vector>

#include "bake/scene.h"

namespace lb {

// Where OIDN's library was loaded from; throws std::runtime_error, one line naming what is
// missing and how to get it, when it cannot be loaded.
std::string require_oidn();

// OIDN's "RT" filter in HDR mode, colour only, over a width x height linear RGB image,
// row-major. (Its "RTLightmap" filter, made for lightmaps' radiance, did less on the shadow
// share at 8 points a cell side in PenumbraTexels: 1.34% mean error against RT's 1.04%, 1.44%
// undenoised.) Throws std::runtime_error with OIDN's own message on failure.
std::vector<vec3> oidn_denoise(int width, int height, const std::vector<vec3>& color);

}  // namespace lb
