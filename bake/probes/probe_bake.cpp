#include "bake/probes/probe_bake.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <glm/gtc/constants.hpp>
#include <stdexcept>
#include <string>

#include "bake/light_sources.h"
#include "bake/sobol_points.h"

namespace lb {

namespace {

// Point k of n of the spherical Fibonacci lattice (Swinbank & Purser 2006), turned by `turn`
// (a fraction of a full turn) about z: equal areas, z at the midpoints of n equal bands, so a
// smooth field's low bands integrate to ~1/n^2 (a uniform field's L1 band exactly to 0 in z),
// where a shifted (0,2)-sequence keeps errors of ~1/n.
vec3 fibonacci_direction(int k, int n, float turn) {
  constexpr double golden_turn = 0.38196601125010515;  // 2 - golden ratio: the golden angle
  const float z = 1.0f - (2.0f * float(k) + 1.0f) / float(n);
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  const double fraction = double(k) * golden_turn + double(turn);
  const float phi = float(2.0 * glm::pi<double>() * (fraction - std::floor(fraction)));
  return {r * std::cos(phi), r * std::sin(phi), z};
}

void add_projected(glm::dvec3* sum, vec3 value, vec3 direction, double weight) {
  const std::array<float, kShCoefficients> y = sh_basis(direction);
  for (int c = 0; c < kShCoefficients; ++c)
    sum[c] += weight * double(y[size_t(c)]) * glm::dvec3(value);
}

}  // namespace

void check_probe_params(const ProbeParams& params) {
  const auto fail = [](const std::string& what) { throw std::invalid_argument(what); };
  if (!(params.spacing >= 0.0f) || !std::isfinite(params.spacing))
    fail("probe spacing must be finite and >= 0 (0: automatic)");
  if (params.max_probes < 1 || params.max_probes > (1 << 20))
    fail("max_probes must be in [1, 1048576]");
  if (params.directions < 1) fail("probe directions must be >= 1");
  if (params.light_samples < 1) fail("probe light_samples must be >= 1");
  if (!(params.invalid_back_fraction >= 0.0f && params.invalid_back_fraction <= 1.0f))
    fail("invalid_back_fraction must be in [0, 1]");
}

ShL2 project_sphere(const std::function<vec3(vec3)>& radiance, int directions, uint64_t shift) {
  glm::dvec3 sum[kShCoefficients];
  std::fill(std::begin(sum), std::end(sum), glm::dvec3(0.0));
  const float turn = float(shift >> 40) * 0x1p-24f;
  for (int k = 0; k < directions; ++k) {
    const vec3 direction = fibonacci_direction(k, directions, turn);
    add_projected(sum, radiance(direction), direction, 4.0 * glm::pi<double>() / directions);
  }
  ShL2 sh;
  for (int c = 0; c < kShCoefficients; ++c) sh[size_t(c)] = vec3(sum[c]);
  return sh;
}

ProbeGrid probe_layout(const Scene& scene, const ProbeParams& params) {
  ProbeGrid grid;
  const Bounds bounds = scene_bounds(scene);
  if (bounds.empty()) return grid;
  const vec3 extent = bounds.extent();
  const float longest = std::max({extent.x, extent.y, extent.z});
  if (!(longest > 0.0f)) return grid;
  float spacing = params.spacing > 0.0f ? params.spacing : longest / 16.0f;
  glm::ivec3 counts;
  for (;;) {
    counts = glm::max(glm::ivec3(glm::ceil(extent / spacing)), glm::ivec3(1));
    if (double(counts.x) * counts.y * counts.z <= double(params.max_probes)) break;
    spacing *= 1.1f;
  }
  grid.counts = counts;
  for (int a = 0; a < 3; ++a) grid.spacing[a] = extent[a] > 0.0f ? extent[a] / float(counts[a]) : spacing;
  grid.origin = bounds.min + 0.5f * grid.spacing;
  grid.valid.assign(grid.size(), 1);
  grid.sh.assign(grid.size(), ShL2{});
  return grid;
}

ProbeSample bake_probe(const GatherContext& context, const LightSources& lights, vec3 position,
                       const ProbeParams& params, uint64_t stream, ProbeStats* stats) {
  const Scene& scene = context.baked.scene;
  glm::dvec3 sum[kShCoefficients];
  std::fill(std::begin(sum), std::end(sum), glm::dvec3(0.0));
  Rng rng(stream);
  GatherCounts counts;
  uint64_t light_rays = 0;

  // Direct light: each light sampled from the probe, radiance / pdf along the sample's way.
  for (size_t light = 0; params.direct && light < lights.size(); ++light) {
    if (lights.kind(light) == LightKind::sky) continue;  // the gather rays see the sky
    const bool area = lights.kind(light) == LightKind::area;
    const int samples = area ? params.light_samples : 1;
    const uint64_t shift = hash_seed(stream, light + 1);
    for (int k = 0; k < samples; ++k) {
      const LightTowards towards =
          lights.sample_towards(light, position, shifted_sobol_point(uint32_t(k), shift));
      if (!(towards.pdf > 0.0f)) continue;
      Ray ray;
      if (std::isinf(towards.distance)) {
        ray.origin = position;
        ray.direction = towards.direction;
      } else {
        const vec3 end = position + towards.direction * towards.distance;
        ray = segment_ray(position, towards.direction, end, towards.direction);
      }
      ++light_rays;
      if (context.accel.occluded(ray)) continue;
      add_projected(sum, towards.radiance / towards.pdf, towards.direction, 1.0 / samples);
    }
  }

  // Everything else: what the gather rays meet.
  int back = 0;
  const ShL2 gathered = project_sphere(
      [&](vec3 direction) {
        Ray ray;
        ray.origin = position;
        ray.direction = direction;
        if (const std::optional<Hit> hit = context.accel.intersect(ray)) {
          const Material& material = scene.materials[size_t(scene.meshes[hit->mesh].material)];
          if (material.is_diffuse() && !material.two_sided_reflection &&
              glm::dot(direction, hit->geometric_normal) >= 0.0f) {
            ++back;  // inside a solid: the back of a one-sided surface, black
            return vec3(0.0f);
          }
        }
        return gathered_radiance(context, ray, rng, counts);
      },
      params.directions, mix64(stream));

  ProbeSample sample;
  for (int c = 0; c < kShCoefficients; ++c)
    sample.sh[size_t(c)] = vec3(sum[c]) + gathered[size_t(c)];
  sample.back_fraction = float(back) / float(params.directions);
  if (stats) {
    stats->rays += counts.rays + uint64_t(params.directions);
    stats->shadow_rays += counts.shadow + light_rays;
  }
  return sample;
}

uint64_t probe_stream(const ProbeParams& params, size_t index) {
  return hash_seed(params.seed, index);
}

ProbeGrid bake_probes(const GatherContext& context, const ProbeParams& params, ProbeStats* stats,
                      const Progress& progress) {
  check_probe_params(params);
  const auto start = std::chrono::steady_clock::now();
  ProbeGrid grid = probe_layout(context.baked.scene, params);
  const LightSources lights(context.baked.scene);
  std::vector<ProbeStats> per_probe(grid.size());
  std::atomic<size_t> done{0};
  tbb::parallel_for(size_t(0), grid.size(), [&](size_t p) {
    if (progress.cancelled()) return;
    const ProbeSample sample = bake_probe(context, lights, grid.position(grid.cell(p)), params,
                                          probe_stream(params, p), &per_probe[p]);
    grid.sh[p] = sample.sh;
    grid.valid[p] = sample.valid(params) ? 1 : 0;
    const size_t finished = ++done;
    if (finished % 256 == 0) progress.update("light probes", double(finished) / double(grid.size()));
  });
  progress.throw_if_cancelled();
  if (stats) {
    *stats = ProbeStats{};
    stats->probes = grid.size();
    for (size_t p = 0; p < grid.size(); ++p) {
      stats->invalid += grid.valid[p] ? 0 : 1;
      stats->rays += per_probe[p].rays;
      stats->shadow_rays += per_probe[p].shadow_rays;
    }
    stats->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return grid;
}

}  // namespace lb
