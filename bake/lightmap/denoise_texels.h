#pragma once
// A lightmap term through Open Image Denoise (oidn.h) the way an atlas needs (issue 36): OIDN
// sees a 2D image, where charts that are neighbours in UV are not neighbours on the surface and
// gutters are empty. So the gutters are first filled from the charts (no black edges for the
// filter to blur in), OIDN's RT filter runs over the whole atlas, only covered texels
// take its output, and each chart keeps its energy: the denoised texels of every 4-connected
// group of covered texels are scaled, per channel, to that group's sum before denoising (the
// estimate's expected energy; OIDN's own shift is reported, not kept). Charts 0 texels apart
// (atlas_padding 2) fall in one group.

#include <cstdint>
#include <vector>

#include "bake/scene.h"

namespace lb {

struct DenoiseStats {
  size_t texels = 0;          // texels that took the denoised value
  size_t groups = 0;          // 4-connected groups of covered texels, each rescaled
  double energy_ratio = 1.0;  // OIDN's (weighted) sum over covered texels / the input's, before
                              // rescaling
  double seconds = 0.0;
};

// `values` width x height; `covered` 1 where a texel holds the term. Uncovered texels keep
// their input. `weight` (width x height, optional): the sums kept are of weight x value (the
// shadow share is kept in the energy of closed form x share). `noisy` (optional): only these
// covered texels take the denoised value, and the sums kept are theirs; the others are exact
// (the ratio estimator's lit and umbra texels) and keep their input; with none noisy OIDN is
// not run. Throws std::runtime_error when OIDN cannot be loaded or fails.
std::vector<vec3> denoise_texels(int width, int height, const std::vector<uint8_t>& covered,
                                 const std::vector<vec3>& values, DenoiseStats* stats = nullptr,
                                 const std::vector<vec3>* weight = nullptr,
                                 const std::vector<uint8_t>* noisy = nullptr);

}  // namespace lb
