// fill_texel_layers (texel_footprint.h) keeps a thread's row buffers from row to row and runs
// the estimator isolated, so a thread waiting on the estimator's own tasks never starts another
// row in those buffers. An estimator with tasks gives the plain fill's bits, and both a linear
// field's value at every node whose footprint lies wholly on the surface (symmetric tents).

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <cmath>

#include "bake/lightmap/texel_footprint.h"
#include "half_atlas_triangle.h"

namespace lb {
namespace {

// Over half_atlas_triangle.h's triangle.
vec3 linear_field(vec3 p) { return vec3(p.x + 2.0f * p.y, 1.0f - p.x, 0.5f + p.y); }

TEST(TexelFill, AnEstimatorWithTasksOfItsOwnGivesThePlainBitsAndTheLinearField) {
  const tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 4);
  const Mesh mesh = half_atlas::triangle();
  constexpr int kWidth = half_atlas::kWidth, kHeight = half_atlas::kHeight;
  const TexelFootprints footprints({&mesh}, kWidth, kHeight);
  const TexelEstimator plain = [](std::span<const FootprintSample> samples,
                                  std::span<vec3> values, size_t) {
    for (size_t s = 0; s < samples.size(); ++s) values[s] = linear_field(samples[s].position);
  };
  // One task a point: while it waits, the thread runs only these.
  const TexelEstimator with_tasks = [](std::span<const FootprintSample> samples,
                                       std::span<vec3> values, size_t) {
    tbb::parallel_for(size_t(0), samples.size(),
                      [&](size_t s) { values[s] = linear_field(samples[s].position); });
  };
  for (const FootprintRule rule : {FootprintRule::quadrature, FootprintRule::stratified}) {
    FillTexelsParams params;
    params.rule = rule;
    params.plane_fit_at_borders = rule == FootprintRule::quadrature;
    const std::vector<vec3> expected = fill_texels(footprints, plain, params);
    for (int run = 0; run < 3; ++run) {
      const std::vector<vec3> got = fill_texels(footprints, with_tasks, params);
      ASSERT_EQ(got.size(), expected.size());
      size_t differing = 0;
      for (size_t k = 0; k < got.size(); ++k) differing += got[k] != expected[k];
      EXPECT_EQ(differing, 0u) << "rule " << int(rule) << ", run " << run;
    }
    if (rule != FootprintRule::quadrature) continue;  // the stratified mean is a noisy one
    // Node (i, j) sits at texel centre ((i + 0.5) / W, (j + 0.5) / H); its footprint, the
    // four cells around it, reaches one texel further each way.
    int interior = 0;
    double worst = 0.0;
    for (int j = 1; j + 1 < kHeight; ++j)
      for (int i = 1; i + 1 < kWidth; ++i) {
        if (float(i + 2) / kWidth + float(j + 2) / kHeight > 1.0f) continue;
        const vec3 node((i + 0.5f) / kWidth, (j + 0.5f) / kHeight, 0.0f);
        const vec3 difference = expected[size_t(j) * kWidth + size_t(i)] - linear_field(node);
        worst = std::max(worst, double(glm::length(difference)));
        ++interior;
      }
    EXPECT_GT(interior, 1000);
    EXPECT_LT(worst, 1e-5) << "a linear field's tent mean is its value at the node";
  }
}

}  // namespace
}  // namespace lb
