#pragma once
// Texel values that bilinear filtering turns back into the light best (issue 36).
//
// fill_texels stores each node's tent-weighted mean of the light. Drawn with bilinear filtering
// those means are blurred twice, once by the tent they average over and once by the filter, so
// at game densities (5-20 texels/m) a shadow edge or the falloff near a light smears over about
// two texels each side. The values x minimising the squared difference between the bilinear
// reconstruction and the light at the footprints' points,
//
//     sum_s area_s (sum_n x_n tent_n(s) - f(s))^2,
//
// solve M x = b, with M_nm = sum_s area_s tent_n(s) tent_m(s) (the Gram matrix of the tents over
// the surface one can see: FillTexelsParams::hidden_triangles drops the rest) and
// b_n = sum_s area_s tent_n(s) f(s) = mean_n weight_n. The means give b, the points' places
// give M, so the step needs no estimate again and runs on a direct term whose shards were
// joined (the same bits). A ridge lambda weight_n (x_n - mean_n) keeps a node with a sliver of
// surface near its mean instead of extrapolating noise, and the result is clamped at zero (light
// is never negative; the projection overshoots a little beside hard shadows).
//
// Energy: sum_n weight_n x_n = sum_n b_n when M x = b (M is symmetric and its rows sum to
// weight_n), so the map holds the same power as the means, less the ridge's and the clamp's
// share (measured in tests/lightmap: within 0.1%).
//
// Noise: the projection undoes the tent's averaging, so it raises the noise of a Monte Carlo
// estimate (about 2.6x in rms for independent points); callers give it more points per texel
// (LightmapParams::direct_side's automatic rule).

#include <span>
#include <vector>

#include "bake/lightmap/texel_footprint.h"
#include "bake/progress.h"

namespace lb {

struct ProjectionParams {
  float ridge = 0.1f;         // lambda above, relative to each node's weight
  int max_iterations = 200;   // conjugate gradients, per colour channel
  double tolerance = 1e-6;    // on the residual's norm relative to the right-hand side's
};

struct ProjectionStats {
  int iterations = 0;         // the most any channel took
  double residual = 0.0;      // the largest relative residual at the end
  size_t clamped_nodes = 0;   // nodes the clamp at zero moved
};

// `means`: fill_texels' values (plane_fit_at_borders off) for the points `points` describes
// (its rule, side, seed and hidden triangles; its rows are ignored: the whole atlas). Nodes with
// no surface keep their value. Deterministic: the same bits whatever the thread count.
// Throws Cancelled when `progress` is cancelled.
std::vector<vec3> project_to_bilinear(const TexelFootprints& footprints,
                                      const FillTexelsParams& points, std::span<const vec3> means,
                                      const ProjectionParams& params = {},
                                      const Progress& progress = {},
                                      ProjectionStats* stats = nullptr);

}  // namespace lb
