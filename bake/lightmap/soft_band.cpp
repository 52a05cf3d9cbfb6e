#include "bake/lightmap/soft_band.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <span>
#include <stdexcept>

#include "bake/accel.h"
#include "bake/lightmap/chart_filter.h"
#include "bake/lightmap/lightmap.h"
#include "bake/lightmap/texel_footprint.h"
#include "bake/lightmap/texel_receiver.h"
#include "bake/sampling.h"
#include "bake/sh_projection.h"
#include "bake/transport/direct_light.h"
#include "bake/transport/final_gather.h"

namespace lb {

namespace {

// noisy_fill with signed values: L1 and normals have no sign.
FillTexelsParams band_fill(int side, uint64_t seed, const char* stage,
                           const std::vector<std::vector<uint8_t>>& hidden) {
  FillTexelsParams fill = noisy_fill(side, seed, stage, hidden);
  fill.signed_values = true;
  return fill;
}

bool bumped(const Scene& scene, const Mesh& surface) {
  return surface.material >= 0 && size_t(surface.material) < scene.materials.size() &&
         scene.materials[size_t(surface.material)].bump != BumpKind::none;
}

}  // namespace

void check_directional_params(const DirectionalParams& p) {
  if (p.gather_rays < 0 || p.gather_rays > 4096 || p.points_side < 1 || p.points_side > 8 ||
      p.filter_radius < 0 || p.filter_radius > 16)
    throw std::invalid_argument("directional lightmaps: gather_rays 0..4096, points_side 1..8, "
                                "filter_radius 0..16");
}

SoftGather gather_soft_l1(const Scene& scene, const BakeResult& bake,
                          const TexelFootprints& footprints,
                          const std::vector<const Mesh*>& surfaces,
                          const std::vector<std::vector<uint8_t>>& hidden,
                          const DirectionalParams& params, uint64_t seed,
                          const Progress& progress) {
  check_directional_params(params);
  const int width = footprints.width(), height = footprints.height();
  const size_t texels = size_t(width) * size_t(height);
  SoftGather out;
  if (params.gather_rays == 0 || texels == 0) {
    for (auto& axis : out.l1) axis.assign(texels, vec3(0.0f));
    out.weight.assign(texels, 0.0);
    return out;
  }
  // The soft map's gather reads the solution itself at its hits (soft_texels.cpp), not a map
  // the bake may already hold.
  BakedScene baked = make_baked_scene(scene, bake);
  baked.soft_texels = nullptr;
  baked.soft_l1 = nullptr;
  const Accel accel(baked.scene);
  const DirectLight direct(baked.scene, accel);
  const GatherContext context{baked, accel, direct};
  std::atomic<uint64_t> gather_rays{0};
  const FillTexelsParams fill = band_fill(params.points_side, hash_seed(seed, 0x5d1),
                                          "soft light's direction", hidden);
  const int rays = params.gather_rays;
  const int m = std::max(1, int(std::sqrt(double(rays))));
  const auto estimate = [&](std::span<const FootprintSample> samples, std::span<vec3> values,
                            size_t cell) {
    const size_t n = samples.size();
    GatherCounts counts;
    for (size_t s = 0; s < n; ++s) {
      const ReceiverPoint x = receiver_at_sample(*surfaces[samples[s].mesh], samples[s]);
      const Frame frame(x.shading_normal);
      Rng rng(hash_seed(fill.seed, cell, s));
      glm::dvec3 sum[3] = {glm::dvec3(0.0), glm::dvec3(0.0), glm::dvec3(0.0)};
      for (int k = 0; k < rays; ++k) {
        const vec2 jitter = rng.next_2d();
        const vec2 u = k < m * m ? stratified(k % m, k / m, m, m, jitter) : jitter;
        const vec3 w = frame.to_world(square_to_uniform_hemisphere(glm::min(u, vec2(0.99999994f))));
        if (glm::dot(w, x.geometric_normal) <= 0.0f) continue;
        Ray ray;
        ray.origin = offset_ray_origin(x.position, x.geometric_normal, w);
        ray.direction = w;
        const vec3 radiance = gathered_radiance(context, ray, rng, counts);
        // pdf 1/(2 pi): the E/pi estimate is 2 L cos.
        const std::array<vec3, 3> band =
            l1_of_sample(2.0f * radiance * glm::dot(w, x.shading_normal), w, x.shading_normal);
        for (size_t a = 0; a < 3; ++a) sum[a] += glm::dvec3(band[a]);
      }
      for (size_t a = 0; a < 3; ++a) values[a * n + s] = vec3(sum[a] / double(rays));
    }
    gather_rays += counts.rays;
  };
  std::vector<std::vector<vec3>> layers =
      fill_texel_layers(footprints, 3, TexelEstimator(estimate), fill, progress, &out.weight);
  for (size_t a = 0; a < 3; ++a)
    out.l1[a] = chart_box_filter(width, height, layers[a], out.weight, params.filter_radius);
  out.rays = gather_rays;
  return out;
}

std::vector<vec3> node_normals(const TexelFootprints& footprints,
                               const std::vector<const Mesh*>& surfaces,
                               const std::vector<std::vector<uint8_t>>& hidden,
                               const Progress& progress) {
  return fill_texels(
      footprints,
      [&](std::span<const FootprintSample> samples, std::span<vec3> values, size_t) {
        for (size_t s = 0; s < samples.size(); ++s)
          values[s] = receiver_at_sample(*surfaces[samples[s].mesh], samples[s]).shading_normal;
      },
      band_fill(1, 0, "normals", hidden), progress);
}

void project_to_tangent_planes(const std::vector<vec3>& normals,
                               std::array<std::vector<vec3>, 3>& l1) {
  for (size_t k = 0; k < normals.size(); ++k) {
    const float length = glm::length(normals[k]);
    if (!(length > 0.0f)) continue;
    const vec3 n = normals[k] / length;
    for (int c = 0; c < 3; ++c) {
      const float along = l1[0][k][c] * n.x + l1[1][k][c] * n.y + l1[2][k][c] * n.z;
      for (int a = 0; a < 3; ++a) l1[size_t(a)][k][c] -= along * n[a];
    }
  }
}

void soft_light_band(const Scene& scene, const BakeResult& bake, SoftTexelMap& map,
                     const DirectionalParams& params, uint64_t seed, int dilation_rings,
                     const Progress& progress) {
  const auto start = std::chrono::steady_clock::now();
  const IlluminationMaps& maps = bake.illumination;
  const int width = maps.width, height = maps.height;
  const size_t texels = size_t(width) * size_t(height);
  for (auto& axis : map.l1) axis.clear();
  map.band_rays = 0;
  if (texels == 0 || map.radiance.size() != texels) return;
  std::vector<Mesh> storage;
  const std::vector<const Mesh*> surfaces = lightmap_surfaces(scene, bake, storage);
  // Only bump- and normal-mapped surfaces take a band: elsewhere n = n0, where every decode is
  // the map itself whatever L1 (tangential) holds. Their points are dropped as hidden ones are.
  bool any_bumped = false;
  for (const Mesh* surface : surfaces)
    any_bumped = any_bumped || (surface && bumped(scene, *surface));
  if (!any_bumped) return;
  const std::vector<std::vector<uint8_t>> skipped = [&] {
    const Accel accel(scene);
    std::vector<std::vector<uint8_t>> flags = hidden_surface_triangles(surfaces, accel);
    flags.resize(surfaces.size());
    for (size_t m = 0; m < surfaces.size(); ++m)
      if (surfaces[m] && !bumped(scene, *surfaces[m]))
        flags[m].assign(surfaces[m]->triangles.size(), 1);
    return flags;
  }();
  const TexelFootprints footprints(surfaces, width, height);
  SoftGather gather =
      gather_soft_l1(scene, bake, footprints, surfaces, skipped, params, seed, progress);
  project_to_tangent_planes(node_normals(footprints, surfaces, skipped, progress), gather.l1);
  std::vector<uint8_t> filled(texels, 0);
  for (size_t k = 0; k < texels; ++k) filled[k] = gather.weight[k] > 0.0 ? 1 : 0;
  for (auto& axis : gather.l1) dilate_texels(width, height, filled, axis, dilation_rings);
  for (size_t k = 0; k < texels; ++k)
    dering(map.radiance[k], gather.l1[0][k], gather.l1[1][k], gather.l1[2][k]);
  map.l1 = std::move(gather.l1);
  map.band_rays = gather.rays;
  map.band_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace lb
