// Convergence: the default room at the default settings against the same solver with many
// more rays (its own executable: the heaviest radiosity test).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "bake/accel.h"
#include "bake/radiosity/radiosity.h"
#include "scenes.h"

namespace lb {
namespace {

// ---- convergence -------------------------------------------------------------------------
TEST(Radiosity, DefaultRoomConvergesToTheManyRayReference) {
  // The issue asks for 64x the rays; that reference is in bench/bench_radiosity.cpp
  // (BM_Convergence64x). Here 8x keeps ctest fast; the reference's own noise is then 35% of
  // the default's (it inflates the measured error by 6% of itself), so the bound stays 3%.
  const Scene scene = test::make_room();
  const Accel accel(scene);
  const RadiosityParams defaults;
  RadiosityParams many = defaults;
  many.ray_budget *= 8;
  many.seed = 99;
  const VertexRadiosity a = solve_radiosity(scene, accel, defaults);
  const VertexRadiosity reference = solve_radiosity(scene, accel, many);
  const double error = mean_relative_error(a, reference);
  std::printf("default %llu rays vs %llu rays: mean relative error %.4f\n",
              (unsigned long long)(a.stats.rays + a.stats.light_rays),
              (unsigned long long)(reference.stats.rays + reference.stats.light_rays), error);
  EXPECT_LT(error, 0.03);
  EXPECT_TRUE(a.stats.converged);
}

}  // namespace
}  // namespace lb
