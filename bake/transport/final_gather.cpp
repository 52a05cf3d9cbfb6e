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

namespace {
// The direct estimate's part to its light's group (context.groups and group_radiance set).
void add_direct_to_group(const GatherGroups* groups, vec3* group_radiance,
                         const DirectEstimate& direct, vec3 weight) {
  if (groups && direct.light >= 0)
    group_radiance[groups->light_group[size_t(direct.light)]] += weight * direct.value;
}
}  // namespace

GatherStop walk_gather_ray(const GatherContext& context, Ray ray, std::optional<Hit> hit,
                           Rng& rng, GatherCounts& counts, const vec2* light_point,
                           vec3* group_radiance) {
  const Scene& scene = context.baked.scene;
  const GatherGroups* groups = group_radiance ? context.groups : nullptr;
  GatherStop stop;
  vec3 throughput(1.0f);
  vec3& radiance = stop.radiance;  // gathered on the way: the backs of two-sided surfaces, the sky
  bool diffuse_before = true;  // the ray left x or the back of a diffuse surface, no mirror between
  for (int depth = 0; depth <= context.max_specular_depth; ++depth) {
    ++counts.rays;
    if (depth > 0) hit = context.accel.intersect(ray);
    if (!hit) {
      // The sky seen straight from x is soft light (pass 2 bakes it so); through specular
      // surfaces it is the illumination maps' (pass 1), already in the term at y.
      const SkyLight* sky = context.direct.sky();
      if (!(diffuse_before && sky)) return stop;
      const vec3 seen = throughput * sky->radiance(glm::normalize(ray.direction));
      if (groups && groups->sky_group >= 0) group_radiance[groups->sky_group] += seen;
      radiance += seen;
      return stop;
    }
    const SurfacePoint sp = surface_at(scene, *hit, ray);
    const Material& material = *sp.material;
    const vec3 direction = glm::normalize(ray.direction);
    if (material.is_diffuse()) {
      const bool back = glm::dot(direction, sp.geometric_normal) >= 0.0f;
      // Back faces absorb, as in the radiosity pass, unless the surface is two-sided;
      // emission is never this term's.
      if (back && !material.two_sided_reflection) return stop;
      const ReceiverPoint y = receiver_at(scene, sp, direction);
      const float u_select = rng.next_float();
      const vec2 drawn = rng.next_2d();  // either way: the next rays' numbers stay the same
      const vec2 u_point = glm::min(light_point ? *light_point : drawn, vec2(0.99999994f));
      if (!back) {
        // The walk ends here: the rest (finish_gather_ray) once the shadow ray is traced.
        stop.direct = context.direct.sample_one_light(y, u_select, u_point, stop.shadow_ray);
        if (stop.direct.shadow_ray) ++counts.shadow;
        stop.at_diffuse = true;
        stop.sp = sp;
        stop.y = y;
        stop.throughput = throughput;
        if (depth == 0 && context.regather_rays > 0 && hit->t < context.regather_distance) {
          const uint64_t high = rng.next_u32();  // two draws in a fixed order, then nonzero
          stop.regather = (high << 32 | rng.next_u32()) | 1u;
        }
        return stop;
      }
      const DirectEstimate direct = context.direct.one_shadow_ray(y, u_select, u_point);
      if (direct.shadow_ray) ++counts.shadow;
      const vec3 reflectance = reflectance_at(scene, sp);
      // The back of a two-sided surface (a thin panel, a leaf): the bake keeps its front's
      // light only, so the back's is gathered here, one more bounce: its direct light, and
      // the light one cosine-distributed ray from its side meets (the pass shoots the back's
      // reflected power from there too; its soft light is not stored).
      radiance += throughput * reflectance * direct.value;
      add_direct_to_group(groups, group_radiance, direct, throughput * reflectance);
      throughput *= reflectance;
      if (!survive_roulette(throughput, kThroughputCutoff, rng)) return stop;
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
    if (!scatter) return stop;
    diffuse_before = false;
    throughput *= scatter->weight;
    if (!survive_roulette(throughput, kThroughputCutoff, rng)) return stop;
    ray.origin = offset_ray_origin(sp.position, sp.geometric_normal, scatter->direction);
    ray.direction = scatter->direction;
    ray.tmin = 0.0f;
    ray.tmax = 1e30f;
  }
  return stop;  // dropped after max_specular_depth bounces
}

vec3 finish_gather_ray(const GatherContext& context, const GatherStop& stop, bool blocked,
                       vec3* group_radiance, GatherCounts& counts) {
  if (!stop.at_diffuse) return stop.radiance;
  const GatherGroups* groups = group_radiance ? context.groups : nullptr;
  const SurfacePoint& sp = stop.sp;
  // DirectLight::one_shadow_ray's estimate, its shadow ray traced by the caller.
  DirectEstimate direct;
  direct.light = stop.direct.light;
  direct.shadow_ray = stop.direct.shadow_ray;
  if (stop.direct.shadow_ray && !blocked) direct.value = stop.direct.value;
  const vec3 reflectance = reflectance_at(context.baked.scene, sp);
  // A short ray's hit gathers its own soft light (GatherContext::regather_distance), each
  // group's part too; the groups' vertex radiosity is then not read.
  std::vector<vec3> regathered_parts;
  vec3 soft;
  if (stop.regather != 0) {
    GatherContext deeper = context;
    deeper.regather_rays = 0;
    if (groups) regathered_parts.resize(groups->count());
    soft = gather_soft_light(deeper, stop.y, stop.regather, context.regather_rays, SampleCell{},
                             &counts, groups ? regathered_parts.data() : nullptr);
  } else {
    soft = soft_light_at(context.baked, sp);
  }
  if (groups) {  // the groups' maps, read together, stand for the whole map
    static const std::vector<std::vector<vec3>> no_vertex_radiance;
    const vec3 weight = stop.throughput * reflectance;
    add_direct_to_group(groups, group_radiance, direct, weight);
    const vec3 map = add_group_terms(
        context.baked, sp, groups->count(), groups->map_start, groups->map_values,
        stop.regather != 0 ? no_vertex_radiance : groups->vertex_radiance, weight, group_radiance);
    for (size_t g = 0; g < regathered_parts.size(); ++g)
      group_radiance[g] += weight * regathered_parts[g];
    return stop.radiance + weight * (direct.value + map + soft);
  }
  const vec3 incident = direct.value + illumination_at(context.baked, sp) + soft;
  return stop.radiance + stop.throughput * reflectance * incident;
}

vec3 gathered_radiance(const GatherContext& context, Ray ray, Rng& rng, GatherCounts& counts,
                       const vec2* light_point, vec3* group_radiance) {
  const GatherStop stop = walk_gather_ray(context, ray, context.accel.intersect(ray), rng, counts,
                                          light_point, group_radiance);
  const bool blocked = stop.at_diffuse && stop.direct.shadow_ray &&
                       context.direct.accel().occluded(stop.shadow_ray);
  return finish_gather_ray(context, stop, blocked, group_radiance, counts);
}

bool gather_ray(const ReceiverPoint& x, const Frame& frame, vec2 unit, Ray& ray) {
  const vec2 u = glm::min(unit, vec2(0.99999994f));
  const vec3 direction = frame.to_world(square_to_cosine_hemisphere(u));
  // A direction above the bumped hemisphere but below the surface meets the surface itself.
  if (glm::dot(direction, x.geometric_normal) <= 0.0f) return false;
  ray.origin = offset_ray_origin(x.position, x.geometric_normal, direction);
  ray.direction = direction;
  ray.tmin = 0.0f;
  ray.tmax = 1e30f;
  return true;
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
    Ray ray;
    if (!gather_ray(x, frame, unit_point(k, rng), ray)) continue;
    const std::optional<vec2> point = light_point(k);
    sum += gathered_radiance(context, ray, rng, count, point ? &*point : nullptr,
                             groups ? group_means : nullptr);
  }
  for (size_t g = 0; g < groups; ++g) group_means[g] /= float(samples);
  return sum / float(samples);
}
}  // namespace

int gather_grid_side(int samples) {
  int m = int(std::sqrt(double(std::max(samples, 0))));
  while ((m + 1) * (m + 1) <= samples) ++m;
  while (m * m > samples) --m;
  return m;
}

vec2 gather_cell_point(int k, int m, const SampleCell& cell, Rng& rng) {
  const vec2 jitter = rng.next_2d();
  const vec2 unit = k < m * m ? stratified(k % m, k / m, m, m, jitter) : jitter;
  return cell.origin + cell.size * unit;
}

vec3 gather_soft_light(const GatherContext& context, const ReceiverPoint& x, uint64_t stream,
                       int samples, const SampleCell& cell, GatherCounts* counts,
                       vec3* group_means) {
  // A jittered m x m grid over the cell, m = floor(sqrt(N)) (compact strata stay compact
  // through the concentric map), and the N - m^2 rays left over uniform over the cell: every
  // ray is uniform over its stratum or the cell, so the mean stays unbiased for any N.
  const int m = gather_grid_side(samples);
  const auto direction_point = [&](int k, Rng& rng) {
    return gather_cell_point(k, m, cell, rng);
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
