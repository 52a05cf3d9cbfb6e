#include "bake/transport/gather_waves.h"

#include <algorithm>
#include <memory>
#include <optional>

namespace lb {

void gather_soft_light_waves(const GatherContext& context, std::span<const GatherPoint> points,
                             int samples, std::span<vec3> means, GatherCounts& counts,
                             std::span<vec3> group_means) {
  const size_t n = points.size();
  const size_t groups = context.groups && !group_means.empty() ? context.groups->count() : 0;
  std::fill(means.begin(), means.begin() + std::ptrdiff_t(n), vec3(0.0f));
  std::fill(group_means.begin(), group_means.end(), vec3(0.0f));
  if (samples < 1 || n == 0) return;
  const int m = gather_grid_side(samples);
  std::vector<Rng> rngs;
  std::vector<Frame> frames;
  rngs.reserve(n);
  frames.reserve(n);
  for (const GatherPoint& p : points) {
    rngs.emplace_back(p.stream);
    frames.emplace_back(p.x.shading_normal);
  }
  std::vector<Ray> rays, shadow_rays;
  std::vector<uint32_t> owner, shadow_owner;  // the point of each ray, the stop of each shadow ray
  std::vector<std::optional<Hit>> hits;
  std::vector<GatherStop> stops;
  const std::unique_ptr<bool[]> blocked(new bool[n]);
  rays.reserve(n);
  owner.reserve(n);
  for (int k = 0; k < samples; ++k) {
    rays.clear();
    owner.clear();
    for (size_t p = 0; p < n; ++p) {
      Ray ray;
      if (!gather_ray(points[p].x, frames[p], gather_cell_point(k, m, points[p].cell, rngs[p]),
                      ray))
        continue;
      rays.push_back(ray);
      owner.push_back(uint32_t(p));
    }
    hits.resize(rays.size());
    context.accel.intersect_many(rays.data(), rays.size(), hits.data(), false);
    stops.resize(rays.size());
    shadow_rays.clear();
    shadow_owner.clear();
    for (size_t i = 0; i < rays.size(); ++i) {
      vec3* parts = groups ? &group_means[owner[i] * groups] : nullptr;
      stops[i] = walk_gather_ray(context, rays[i], hits[i], rngs[owner[i]], counts, nullptr, parts);
      if (stops[i].at_diffuse && stops[i].direct.shadow_ray) {
        shadow_rays.push_back(stops[i].shadow_ray);
        shadow_owner.push_back(uint32_t(i));
      }
    }
    // Through the direct light's accelerator (final_gather.h: finish_gather_ray).
    context.direct.accel().occluded_many(shadow_rays.data(), shadow_rays.size(), blocked.get(),
                                         false);
    size_t next_shadow = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
      const bool traced = next_shadow < shadow_owner.size() && shadow_owner[next_shadow] == i;
      const bool is_blocked = traced && blocked[next_shadow];
      next_shadow += traced;
      vec3* parts = groups ? &group_means[owner[i] * groups] : nullptr;
      means[owner[i]] += finish_gather_ray(context, stops[i], is_blocked, parts, counts);
    }
  }
  for (size_t p = 0; p < n; ++p) means[p] /= float(samples);
  for (vec3& part : group_means) part /= float(samples);
}

}  // namespace lb
