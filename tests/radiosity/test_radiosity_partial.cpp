// Partial results of a running solve (the viewer's live refinement): the hook is called as
// often as asked, each partial is the solution so far (received power only grows, so every
// vertex only brightens, towards the final result, and the partial after the last shot is
// the final result), and the hook changes no bit of the result. The same for bake_scene.

#include <gtest/gtest.h>

#include <cstdio>
#include <cmath>
#include <cstring>
#include <vector>

#include "bake/accel.h"
#include "bake/pipeline/bake.h"
#include "bake/radiosity/radiosity.h"
#include "scenes.h"
#include "test_helpers.h"

namespace lb {
namespace {

using test::same_bits;

bool same_bits(const VertexRadiosity& a, const VertexRadiosity& b) {
  if (a.meshes.size() != b.meshes.size()) return false;
  for (size_t m = 0; m < a.meshes.size(); ++m)
    if (!same_bits(a.meshes[m].vertex_radiance, b.meshes[m].vertex_radiance) ||
        !same_bits(a.meshes[m].mesh.positions, b.meshes[m].mesh.positions) ||
        !same_bits(a.meshes[m].triangle_patch, b.meshes[m].triangle_patch))
      return false;
  return true;
}

// Area-weighted mean of the (linearly interpolated) vertex radiance over all radiosity
// meshes, per channel, W/(sr m^2).
glm::dvec3 mean_radiance(const VertexRadiosity& r) {
  glm::dvec3 sum(0.0);
  double area = 0.0;
  for (const MeshRadiosity& mr : r.meshes)
    for (size_t t = 0; t < mr.mesh.triangles.size(); ++t) {
      const uvec3 tri = mr.mesh.triangles[t];
      const double a = triangle_area(mr.mesh, t);
      sum += a *
             glm::dvec3(mr.vertex_radiance[tri.x] + mr.vertex_radiance[tri.y] +
                        mr.vertex_radiance[tri.z]) /
             3.0;
      area += a;
    }
  return area > 0.0 ? sum / area : sum;
}

RadiosityParams room_params() {
  RadiosityParams params;
  params.ray_budget = 300'000;
  params.seed = 3;
  // The automatic size before issue 11 (~170 patches): these tests keep every partial, and
  // ~1500 patches make ~8x the shots and partials.
  params.patch_size = std::sqrt(16.0f / 32.0f);
  return params;
}

TEST(RadiosityPartial, HookCalledEveryNShotsAndNeverWhenTooSoon) {
  const Scene scene = test::make_room();
  const Accel accel(scene);
  RadiosityCallbacks callbacks;
  callbacks.min_interval_seconds = 0.0;
  callbacks.min_interval_shots = 50;
  std::vector<uint64_t> shots;
  callbacks.on_partial = [&](const VertexRadiosity& partial) {
    shots.push_back(partial.stats.shots);
  };
  const VertexRadiosity result = solve_radiosity(scene, accel, room_params(), {}, callbacks);
  ASSERT_TRUE(result.stats.converged);
  // Exactly after shots 50, 100, ...: the count is a function of the shot count alone.
  ASSERT_GT(shots.size(), 1u);
  EXPECT_EQ(shots.size(), result.stats.shots / 50);
  for (size_t i = 0; i < shots.size(); ++i) EXPECT_EQ(shots[i], 50 * (i + 1));

  // A time interval longer than the solve: never called.
  callbacks.min_interval_seconds = 1e9;
  callbacks.min_interval_shots = 1;
  shots.clear();
  solve_radiosity(scene, accel, room_params(), {}, callbacks);
  EXPECT_TRUE(shots.empty());
}

TEST(RadiosityPartial, PartialsBrightenTowardsTheFinalResultWhichIsUnchanged) {
  const Scene scene = test::make_room();
  const Accel accel(scene);
  const VertexRadiosity plain = solve_radiosity(scene, accel, room_params());

  RadiosityCallbacks callbacks;
  callbacks.min_interval_seconds = 0.0;
  callbacks.min_interval_shots = 1;  // after every shot, the last one included
  std::vector<VertexRadiosity> partials;
  callbacks.on_partial = [&](const VertexRadiosity& partial) { partials.push_back(partial); };
  const VertexRadiosity hooked = solve_radiosity(scene, accel, room_params(), {}, callbacks);

  // (3) The hook only reads: the same bits and the same work.
  EXPECT_TRUE(same_bits(plain, hooked));
  EXPECT_EQ(plain.stats.shots, hooked.stats.shots);
  EXPECT_EQ(plain.stats.rays, hooked.stats.rays);
  EXPECT_EQ(std::memcmp(&plain.stats.residual_unsent, &hooked.stats.residual_unsent, sizeof(vec3)),
            0);
  EXPECT_EQ(std::memcmp(&plain.stats.power_absorbed, &hooked.stats.power_absorbed, sizeof(vec3)),
            0);

  ASSERT_EQ(partials.size(), hooked.stats.shots);
  // (2) Received power only grows and the conversion to vertices is monotone (non-negative
  // weights), so every vertex of every partial is at most its value in the next partial and
  // in the final result: exactly, no tolerance.
  auto at_most = [](const VertexRadiosity& earlier, const VertexRadiosity& later) {
    for (size_t m = 0; m < earlier.meshes.size(); ++m) {
      const auto& a = earlier.meshes[m].vertex_radiance;
      const auto& b = later.meshes[m].vertex_radiance;
      if (a.size() != b.size()) return false;
      for (size_t v = 0; v < a.size(); ++v)
        if (!glm::all(glm::lessThanEqual(a[v], b[v]))) return false;
    }
    return true;
  };
  const VertexRadiosity* previous = nullptr;
  for (size_t i = 0; i < partials.size(); ++i) {
    const VertexRadiosity& partial = partials[i];
    ASSERT_EQ(partial.meshes.size(), hooked.meshes.size());
    EXPECT_FALSE(partial.stats.converged);
    EXPECT_EQ(partial.stats.shots, i + 1);
    EXPECT_TRUE(at_most(partial, hooked)) << "partial " << i << " exceeds the final result";
    if (previous) {
      EXPECT_TRUE(at_most(*previous, partial)) << "partial " << i << " darkened";
      // The unsent power falls (up to the rounding of the exact recomputation).
      EXPECT_LE(partial.stats.residual_fraction,
                previous->stats.residual_fraction * (1.0 + 1e-9) + 1e-12);
    }
    previous = &partial;
  }
  // The area-weighted means climb to the final one; the first partial is far from it, so the
  // checks above compare different things (measured: first 0.9%, halfway 96%).
  const double final_mean = mean_radiance(hooked).x;
  const double first_mean = mean_radiance(partials.front()).x;
  const double halfway_mean = mean_radiance(partials[partials.size() / 2]).x;
  std::printf("mean radiance: first partial %.5g, halfway %.5g, final %.5g (%zu partials)\n",
              first_mean, halfway_mean, final_mean, partials.size());
  EXPECT_GT(final_mean, 0.0);
  EXPECT_LT(first_mean, 0.5 * final_mean);
  EXPECT_LE(halfway_mean, final_mean);
  // The partial after the last shot is the final result, bit for bit.
  EXPECT_TRUE(same_bits(partials.back(), hooked));
}

TEST(RadiosityPartial, BakeSceneForwardsPartialsAndKeepsItsBits) {
  const Scene scene = test::make_room();
  BakeParams params;
  params.illumination.rays_per_zone_side = 16;
  params.radiosity.ray_budget = 200'000;
  // A few hundred shots show the forwarding as well as the converged thousands (each partial
  // compares megabytes of maps), at a tenth of the time.
  params.radiosity.max_shots = 300;
  params.seed = 5;
  const BakeResult plain = bake_scene(scene, params);

  BakeCallbacks callbacks;
  callbacks.min_interval_seconds = 0.0;
  // The partials keep their radiosity; the maps (an atlas of every diffuse mesh, megabytes,
  // one per shot) are checked as they come, against the plain bake's.
  struct Partial {
    uint64_t seed = 0;
    bool same_maps = false;
    size_t uv_meshes = 0;
    VertexRadiosity radiosity;
  };
  std::vector<Partial> partials;
  callbacks.on_partial = [&](const BakeResult& partial) {
    partials.push_back({partial.seed,
                        same_bits(partial.illumination.radiance, plain.illumination.radiance),
                        partial.illumination.lightmap_uvs.size(), partial.radiosity});
  };
  const BakeResult hooked = bake_scene(scene, params, {}, callbacks);

  EXPECT_TRUE(same_bits(plain.radiosity, hooked.radiosity));
  EXPECT_TRUE(same_bits(plain.illumination.radiance, hooked.illumination.radiance));
  // First the maps alone (pass 1 complete), then one partial per radiosity shot.
  ASSERT_EQ(partials.size(), 1 + hooked.radiosity.stats.shots);
  EXPECT_TRUE(partials.front().radiosity.meshes.empty());
  for (const Partial& partial : partials) {
    EXPECT_EQ(partial.seed, hooked.seed);
    EXPECT_TRUE(partial.same_maps);
    EXPECT_EQ(partial.uv_meshes, hooked.illumination.lightmap_uvs.size());
  }
  EXPECT_LE(mean_radiance(partials[1].radiosity).x, mean_radiance(hooked.radiosity).x);
  EXPECT_TRUE(same_bits(partials.back().radiosity, hooked.radiosity));
}

}  // namespace
}  // namespace lb
