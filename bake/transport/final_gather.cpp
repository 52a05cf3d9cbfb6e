#include "bake/transport/final_gather.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "bake/bsdf.h"
#include "bake/bump.h"
#include "bake/transport/baked_terms.h"
#include "bake/sobol_points.h"
#include "bake/surface.h"

namespace lb {

namespace {
// Below this throughput (max channel) Russian roulette decides whether a specular chain goes
// on, as in HQ's viewing paths: unbiased, and weak chains stop early.
constexpr float kThroughputCutoff = 0.01f;
}  // namespace

ReceiverPoint receiver_at(const Scene& scene, const SurfacePoint& sp, vec3 arrival) {
  const float side = glm::dot(arrival, sp.geometric_normal) < 0.0f ? 1.0f : -1.0f;
  ReceiverPoint x;
  x.position = sp.position;
  x.geometric_normal = side * sp.geometric_normal;
  x.shading_normal = side * bumped_normal(scene, sp);
  if (glm::dot(x.shading_normal, x.geometric_normal) <= 0.0f) x.shading_normal = x.geometric_normal;
  return x;
}

vec3 gathered_radiance(const GatherContext& context, Ray ray, Rng& rng, GatherCounts& counts,
                       const vec2* light_point, vec3* group_radiance) {
  const Scene& scene = context.baked.scene;
  const GatherGroups* groups = group_radiance ? context.groups : nullptr;
  // The direct estimate's part to its light's group.
  const auto add_direct = [&](const DirectEstimate& direct, vec3 weight) {
    if (groups && direct.light >= 0)
      group_radiance[groups->light_group[size_t(direct.light)]] += weight * direct.value;
  };
  vec3 throughput(1.0f);
  vec3 radiance(0.0f);   // gathered on the way: the light the backs of two-sided surfaces reflect
  bool diffuse_before = true;  // the ray left x or the back of a diffuse surface, no mirror between
  for (int depth = 0; depth <= context.max_specular_depth; ++depth) {
    ++counts.rays;
    const std::optional<Hit> hit = context.accel.intersect(ray);
    if (!hit) {
      // The sky seen straight from x is soft light (pass 2 bakes it so); through specular
      // surfaces it is the illumination maps' (pass 1), already in the term at y.
      const SkyLight* sky = context.direct.sky();
      if (!(diffuse_before && sky)) return radiance;
      const vec3 seen = throughput * sky->radiance(glm::normalize(ray.direction));
      if (groups && groups->sky_group >= 0) group_radiance[groups->sky_group] += seen;
      return radiance + seen;
    }
    const SurfacePoint sp = surface_at(scene, *hit, ray);
    const Material& material = *sp.material;
    const vec3 direction = glm::normalize(ray.direction);
    if (material.is_diffuse()) {
      const bool back = glm::dot(direction, sp.geometric_normal) >= 0.0f;
      // Back faces absorb, as in the radiosity pass, unless the surface is two-sided;
      // emission is never this term's.
      if (back && !material.two_sided_reflection) return radiance;
      const ReceiverPoint y = receiver_at(scene, sp, direction);
      const float u_select = rng.next_float();
      const vec2 drawn = rng.next_2d();  // either way: the next rays' numbers stay the same
      const vec2 u_point = glm::min(light_point ? *light_point : drawn, vec2(0.99999994f));
      const DirectEstimate direct = context.direct.one_shadow_ray(y, u_select, u_point);
      if (direct.shadow_ray) ++counts.shadow;
      const vec3 reflectance = reflectance_at(scene, sp);
      if (!back) {
        if (groups) {  // the groups' maps, read together, stand for the whole map
          const vec3 weight = throughput * reflectance;
          add_direct(direct, weight);
          const vec3 map =
              add_group_terms(context.baked, sp, groups->count(), groups->map_start,
                              groups->map_values, groups->vertex_radiance, weight, group_radiance);
          return radiance + weight * (direct.value + map + soft_light_at(context.baked, sp));
        }
        const vec3 incident =
            direct.value + illumination_at(context.baked, sp) + soft_light_at(context.baked, sp);
        return radiance + throughput * reflectance * incident;
      }
      // The back of a two-sided surface (a thin panel, a leaf): the bake keeps its front's
      // light only, so the back's is gathered here, one more bounce: its direct light, and
      // the light one cosine-distributed ray from its side meets (the pass shoots the back's
      // reflected power from there too; its soft light is not stored).
      radiance += throughput * reflectance * direct.value;
      add_direct(direct, throughput * reflectance);
      throughput *= reflectance;
      if (!survive_roulette(throughput, kThroughputCutoff, rng)) return radiance;
      const vec3 next = Frame(y.geometric_normal).to_world(square_to_cosine_hemisphere(
          glm::min(rng.next_2d(), vec2(0.99999994f))));
      ray.origin = offset_ray_origin(y.position, y.geometric_normal, next);
      ray.direction = next;
      ray.tmin = 0.0f;
      ray.tmax = 1e30f;
      light_point = nullptr;  // the next hit's light point from rng
      diffuse_before = true;
      continue;
    }
    const std::optional<SpecularScatter> scatter =
        scatter_specular(material, direction, specular_normal(scene, sp, direction), rng.next_2d());
    if (!scatter) return radiance;
    diffuse_before = false;
    throughput *= scatter->weight;
    if (!survive_roulette(throughput, kThroughputCutoff, rng)) return radiance;
    ray.origin = offset_ray_origin(sp.position, sp.geometric_normal, scatter->direction);
    ray.direction = scatter->direction;
    ray.tmin = 0.0f;
    ray.tmax = 1e30f;
  }
  return radiance;  // dropped after max_specular_depth bounces
}

namespace {
// The mean of `samples` gather rays from x, ray k leaving along the cosine-weighted direction
// of unit_point(k, rng) in [0, 1)^2, its hit's light point light_point(k) (none: from rng).
template <class UnitPoint, class LightPoint>
vec3 gather_mean(const GatherContext& context, const ReceiverPoint& x, uint64_t stream,
                 int samples, GatherCounts* counts, UnitPoint unit_point,
                 LightPoint light_point, vec3* group_means = nullptr) {
  const size_t groups = group_means && context.groups ? context.groups->count() : 0;
  for (size_t g = 0; g < groups; ++g) group_means[g] = vec3(0.0f);
  if (samples < 1) return vec3(0.0f);
  Rng rng(stream);
  GatherCounts local;
  GatherCounts& count = counts ? *counts : local;
  const Frame frame(x.shading_normal);
  vec3 sum(0.0f);
  for (int k = 0; k < samples; ++k) {
    const vec2 u = glm::min(unit_point(k, rng), vec2(0.99999994f));
    const vec3 direction = frame.to_world(square_to_cosine_hemisphere(u));
    // A direction above the bumped hemisphere but below the surface meets the surface itself.
    if (glm::dot(direction, x.geometric_normal) <= 0.0f) continue;
    Ray ray;
    ray.origin = offset_ray_origin(x.position, x.geometric_normal, direction);
    ray.direction = direction;
    const std::optional<vec2> point = light_point(k);
    sum += gathered_radiance(context, ray, rng, count, point ? &*point : nullptr,
                             groups ? group_means : nullptr);
  }
  for (size_t g = 0; g < groups; ++g) group_means[g] /= float(samples);
  return sum / float(samples);
}
}  // namespace

vec3 gather_soft_light(const GatherContext& context, const ReceiverPoint& x, uint64_t stream,
                       int samples, const SampleCell& cell, GatherCounts* counts,
                       vec3* group_means) {
  // A jittered m x m grid over the cell, m = floor(sqrt(N)) (compact strata stay compact
  // through the concentric map), and the N - m^2 rays left over uniform over the cell: every
  // ray is uniform over its stratum or the cell, so the mean stays unbiased for any N.
  int m = int(std::sqrt(double(std::max(samples, 0))));
  while ((m + 1) * (m + 1) <= samples) ++m;
  while (m * m > samples) --m;
  const auto direction_point = [&](int k, Rng& rng) {
    const vec2 jitter = rng.next_2d();
    const vec2 unit = k < m * m ? stratified(k % m, k / m, m, m, jitter) : jitter;
    return cell.origin + cell.size * unit;
  };
  const auto light_point = [](int) { return std::optional<vec2>(); };
  return gather_mean(context, x, stream, samples, counts, direction_point, light_point,
                     group_means);
}

vec3 gather_soft_light(const GatherContext& context, const ReceiverPoint& x, uint64_t stream,
                       int samples, const SobolStrata& strata, GatherCounts* counts) {
  const uint64_t light_shift = mix64(strata.shift);
  const auto direction_point = [&](int k, Rng&) {
    return shifted_sobol_point(strata.first_index + uint32_t(k), strata.shift);
  };
  const auto light_point = [&](int k) {
    return std::optional<vec2>(
        shifted_sobol_point(strata.first_index + uint32_t(k), light_shift, 2));
  };
  return gather_mean(context, x, stream, samples, counts, direction_point, light_point);
}

}  // namespace lb
