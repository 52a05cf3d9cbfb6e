#include "bake/transport/direct_light.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "bake/sampling.h"
#include "bake/transport/eq2_sweep.h"

namespace lb {

namespace {
constexpr float kInvPi = std::numbers::inv_pi_v<float>;
}

DirectLight::DirectLight(const Scene& scene, const Accel& accel)
    : scene_(scene), accel_(accel), sources_(scene) {
  for (size_t i = 0; i < sources_.size(); ++i) {
    const LightKind kind = sources_.kind(i);
    const bool lamp =
        kind == LightKind::point || kind == LightKind::spot || kind == LightKind::directional;
    if (lamp && sources_.lamp(i).intensity != vec3(0.0f)) lamps_.push_back(i);
  }
  for (const AreaLight& light : lights()) {
    const Mesh& mesh = scene.meshes[size_t(light.mesh)];
    float radius = 0.0f;
    bool planar = true;
    const float tolerance = 1e-4f * std::sqrt(light.area) + 1e-6f;
    for (uint32_t t : light.triangles) {
      const uvec3 tri = mesh.triangles[t];
      for (int k = 0; k < 3; ++k) {
        const vec3 p = mesh.positions[tri[k]];
        radius = std::max(radius, glm::length(p - light.centroid));
        if (std::abs(glm::dot(p - light.centroid, light.normal)) > tolerance) planar = false;
      }
      if (glm::dot(triangle_normal(mesh, t), light.normal) < 0.9999f) planar = false;
    }
    cx_.push_back(light.centroid.x);
    cy_.push_back(light.centroid.y);
    cz_.push_back(light.centroid.z);
    nx_.push_back(light.normal.x);
    ny_.push_back(light.normal.y);
    nz_.push_back(light.normal.z);
    radius_.push_back(radius);
    lum_area_.push_back(std::max(luminance(light.radiance), 0.0f) * light.area * kInvPi);
    min_d2_.push_back(0.25f * light.area);
    planar_.push_back(planar ? 1.0f : 0.0f);
    if (!planar) non_planar_.push_back(uint32_t(planar_.size() - 1));
    if (planar && light.two_sided) two_sided_.push_back(uint32_t(planar_.size() - 1));
  }
  sample_first_.push_back(0);
  for (const AreaLight& light : lights()) {
    const Mesh& mesh = scene.meshes[size_t(light.mesh)];
    for (size_t i = 0; i < light.triangles.size(); ++i) {
      const uvec3 tri = mesh.triangles[light.triangles[i]];
      sample_cdf_.push_back(light.triangle_cdf[i]);
      sample_triangles_.push_back({mesh.positions[tri.x], mesh.positions[tri.y],
                                   mesh.positions[tri.z], light.triangle_normals[i]});
    }
    sample_first_.push_back(uint32_t(sample_cdf_.size()));
  }
  static_assert(sizeof(LightRecord) == 128, "two cache lines");
  records_.resize(lights().size());
  for (size_t j = 0; j < lights().size(); ++j) {
    const AreaLight& light = lights()[j];
    LightRecord& record = records_[j];
    record.count = sample_first_[j + 1] - sample_first_[j];
    for (uint32_t i = 0; i < std::min(record.count, 2u); ++i) {
      record.triangles[i] = sample_triangles_[sample_first_[j] + i];
      record.cdf[i] = sample_cdf_[sample_first_[j] + i];
    }
    record.radiance = light.radiance;
    record.area = light.area;
    record.two_sided = light.two_sided;
  }
}

double DirectLight::eq2_weights(const ReceiverPoint& x, float* weights, int& reachable) const {
  const size_t count = lights().size();
  const float* cx = cx_.data();
  const float* cy = cy_.data();
  const float* cz = cz_.data();
  const float* nx = nx_.data();
  const float* ny = ny_.data();
  const float* nz = nz_.data();
  const float* radius = radius_.data();
  const float* lum_area = lum_area_.data();
  const float* min_d2 = min_d2_.data();
  float* out = weights;
  // Computed as if every light were planar (the others are redone below), with the sums that
  // hold when they are all planar and one-sided (eq2_sweep.h).
  float partial[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  int reachable_count = 0;
  eq2_sweep({cx, cy, cz, nx, ny, nz, radius, lum_area, min_d2, count},
            {x.position.x, x.position.y, x.position.z, x.geometric_normal.x,
             x.geometric_normal.y, x.geometric_normal.z, x.shading_normal.x, x.shading_normal.y,
             x.shading_normal.z},
            out, partial, reachable_count);
  if (non_planar_.empty() && two_sided_.empty() && lamps_.empty()) {
    reachable = reachable_count;
    return double((partial[0] + partial[1]) + (partial[2] + partial[3]));
  }
  // A non-planar light has no single orientation: reachable if its bounding sphere reaches
  // above x's plane, and counted as facing x (cos_y = 1).
  for (const uint32_t j : non_planar_) {
    const vec3 v = vec3(cx[j], cy[j], cz[j]) - x.position;
    const float d2 = glm::dot(v, v);
    out[j] = glm::dot(x.geometric_normal, v) > -radius[j]
                 ? lum_area[j] * std::max(glm::dot(x.shading_normal, v), 0.0f) * std::sqrt(d2) /
                       (d2 * std::max(d2, min_d2[j]))
                 : -1.0f;
  }
  // A planar two-sided light faces x from either side: |cos_y|.
  for (const uint32_t j : two_sided_) {
    const vec3 v = vec3(cx[j], cy[j], cz[j]) - x.position;
    const float d2 = glm::dot(v, v);
    const float facing = std::abs(glm::dot(vec3(nx[j], ny[j], nz[j]), v));
    const float above = glm::dot(x.geometric_normal, v) + radius[j];
    const float cos_x_d = std::max(glm::dot(x.shading_normal, v), 0.0f);
    out[j] = std::min(above, facing) > 0.0f
                 ? lum_area[j] * cos_x_d * facing / (d2 * std::max(d2, min_d2[j]))
                 : -1.0f;
  }
  // Lamps: Eq. 2 is their exact unshadowed value.
  for (size_t k = 0; k < lamps_.size(); ++k) {
    float weight = 0.0f;
    const bool lit = lamp_towards(x, count + k, weight).pdf > 0.0f;
    out[count + k] = lit ? weight : -1.0f;
  }
  const size_t total = light_count();
  // Four partial sums in a fixed order: vectorisable and the same bits on every thread.
  std::fill(partial, partial + 4, 0.0f);
  reachable_count = 0;
  size_t j = 0;
  for (; j + 4 <= total; j += 4)
    for (size_t k = 0; k < 4; ++k) {
      partial[k] += std::max(out[j + k], 0.0f);
      reachable_count += out[j + k] >= 0.0f ? 1 : 0;
    }
  for (; j < total; ++j) {
    partial[0] += std::max(out[j], 0.0f);
    reachable_count += out[j] >= 0.0f ? 1 : 0;
  }
  reachable = reachable_count;
  return double((partial[0] + partial[1]) + (partial[2] + partial[3]));
}

LightTowards DirectLight::lamp_towards(const ReceiverPoint& x, size_t light, float& weight) const {
  LightTowards t = sources_.sample_towards(lamps_[light - lights().size()], x.position, vec2(0.5f));
  const float cos_x = glm::dot(x.shading_normal, t.direction);
  // Below the geometric surface or behind the bumped normal: no light.
  if (!(cos_x > 0.0f) || glm::dot(x.geometric_normal, t.direction) <= 0.0f) t.pdf = 0.0f;
  if (!(t.pdf > 0.0f)) {
    weight = 0.0f;
    return t;
  }
  t.radiance *= cos_x * kInvPi;  // E/pi, f_j / p_j with p_j = 1
  weight = luminance(t.radiance);
  return t;
}

bool DirectLight::can_reach(const ReceiverPoint& x, size_t light) const {
  std::vector<float> weights(light_count());
  int reachable = 0;
  eq2_weights(x, weights.data(), reachable);
  return weights[light] >= 0.0f;
}

float DirectLight::eq2_estimate(const ReceiverPoint& x, size_t light) const {
  std::vector<float> weights(light_count());
  int reachable = 0;
  eq2_weights(x, weights.data(), reachable);
  return std::max(weights[light], 0.0f);
}

std::vector<float> DirectLight::selection_probabilities(const ReceiverPoint& x) const {
  std::vector<float> p(light_count(), 0.0f);
  int reachable = 0;
  const double total = eq2_weights(x, p.data(), reachable);
  if (reachable == 0) {
    std::fill(p.begin(), p.end(), 0.0f);
    return p;
  }
  const float share = total > 0.0 ? kUniformShare : 1.0f;
  const float uniform = share / float(reachable);
  const double scale = total > 0.0 ? (1.0 - share) / total : 0.0;
  for (float& w : p) w = w < 0.0f ? 0.0f : float(w * scale) + uniform;
  return p;
}

bool DirectLight::unoccluded_contribution(const ReceiverPoint& x, size_t light, vec2 u_point,
                                          vec3& f_over_pdf, Ray& shadow_ray) const {
  if (light >= lights().size()) {
    float weight = 0.0f;
    const LightTowards t = lamp_towards(x, light, weight);
    if (!(t.pdf > 0.0f)) return false;
    shadow_ray = shadow_ray_towards(x.position, x.geometric_normal, t);
    f_over_pdf = t.radiance;
    return true;
  }
  // AreaLight::sample's point, from the packed copy of the light's triangles.
  const LightRecord& record = records_[light];
  const SampleTriangle* triangles = record.triangles;
  const float* cdf = record.cdf;
  if (record.count > 2) {
    triangles = sample_triangles_.data() + sample_first_[light];
    cdf = sample_cdf_.data() + sample_first_[light];
  }
  const PickedTriangle picked = pick_triangle(cdf, record.count, u_point.x);
  const SampleTriangle& triangle = triangles[picked.index];
  // Loose values, not a LightSample: its normal packed after the point was read back across
  // two stores (a failed store forward per shadow ray, perf on the room's render).
  const vec3 position = point_on_triangle(triangle.p0, triangle.p1, triangle.p2,
                                          square_to_triangle({picked.u_x, u_point.y}));
  const vec3& normal = triangle.normal;
  const vec3 to_light = position - x.position;
  const float d2 = glm::dot(to_light, to_light);
  if (!(d2 > 0.0f)) return false;
  const float inv_d = 1.0f / std::sqrt(d2);
  const vec3 w = to_light * inv_d;
  const float cos_x = glm::dot(x.shading_normal, w);
  const float emitting = glm::dot(normal, -w);  // AreaLight::emitting_cosine
  const float cos_y = record.two_sided ? std::abs(emitting) : emitting;
  // Below the geometric surface, behind the bumped normal or behind the emitter: no light.
  if (cos_x <= 0.0f || cos_y <= 0.0f || glm::dot(x.geometric_normal, w) <= 0.0f) return false;
  segment_ray(x.position, x.geometric_normal, position, normal, shadow_ray);
  // f(y) / pdf(y) with pdf = 1/A.
  f_over_pdf = record.radiance * (cos_x * cos_y * kInvPi / d2 * record.area);
  return true;
}

vec3 DirectLight::contribution(const ReceiverPoint& x, size_t light, vec2 u_point,
                               bool& traced) const {
  vec3 f_over_pdf(0.0f);
  Ray shadow_ray;
  traced = unoccluded_contribution(x, light, u_point, f_over_pdf, shadow_ray);
  return traced && !accel_.occluded(shadow_ray) ? f_over_pdf : vec3(0.0f);
}

DirectEstimate DirectLight::traced(const DeferredEstimate& deferred, const Ray& shadow_ray) const {
  DirectEstimate estimate;
  estimate.light = deferred.light;
  estimate.shadow_ray = deferred.shadow_ray;
  if (deferred.shadow_ray && !accel_.occluded(shadow_ray)) estimate.value = deferred.value;
  return estimate;
}

DirectEstimate DirectLight::one_shadow_ray(const ReceiverPoint& x, float u_select,
                                           vec2 u_point) const {
  Ray shadow_ray;
  const DeferredEstimate deferred = sample_one_light(x, u_select, u_point, shadow_ray);
  return traced(deferred, shadow_ray);
}

DeferredEstimate DirectLight::sample_one_light(const ReceiverPoint& x, float u_select, vec2 u_point,
                                               Ray& shadow_ray) const {
  DeferredEstimate estimate;
  // Per-thread scratch for the weights, so a hit allocates nothing.
  thread_local std::vector<float> weights;
  const size_t count = light_count();
  if (weights.size() < count) weights.resize(count);
  int reachable = 0;
  const double total = eq2_weights(x, weights.data(), reachable);
  if (reachable == 0) return estimate;  // no light can reach x: no shadow ray (the ceiling)
  const float share = total > 0.0 ? kUniformShare : 1.0f;
  const float uniform = share / float(reachable);
  const double scale = total > 0.0 ? (1.0 - share) / total : 0.0;

  // Invert the discrete distribution p_j = scale * w_j + uniform over the reachable lights,
  // in units of `scale` so the running sum is one add per light. (With all w_j = 0, scale = 0:
  // every reachable light counts 1 and the target is u * M.)
  const float per_light = scale > 0.0 ? float(uniform / scale) : 1.0f;
  const float target = scale > 0.0 ? float(double(u_select) / scale) : u_select / uniform;
  float cumulative = 0.0f;
  size_t chosen = count;
  for (size_t j = 0; j < count; ++j) {
    if (weights[j] < 0.0f) continue;
    chosen = j;  // the last reachable one absorbs rounding when u_select is near 1
    cumulative += weights[j] + per_light;
    if (target < cumulative) break;
  }
  const float chosen_p = float(weights[chosen] * scale) + uniform;
  estimate.light = int(chosen);
  vec3 f_over_pdf(0.0f);
  estimate.shadow_ray = unoccluded_contribution(x, chosen, u_point, f_over_pdf, shadow_ray);
  estimate.value = f_over_pdf / chosen_p;
  return estimate;
}

void DirectLight::prepare_choice(const ReceiverPoint& anchor, uint32_t mesh, Choice& choice) const {
  const size_t count = light_count();
  const size_t padded = (count + kChoiceBlock - 1) / kChoiceBlock * kChoiceBlock;
  choice.cdf.resize(padded);
  choice.lights = count;
  choice.anchor = anchor.position;
  choice.normal = anchor.geometric_normal;
  choice.mesh = mesh;
  choice.valid = true;
  if (count == 0) return;
  int reachable = 0;
  const double total = eq2_weights(anchor, choice.cdf.data(), reachable);
  const double share = total > 0.0 ? double(kUniformShare) : 1.0;
  const double scale = total > 0.0 ? (1.0 - share) / total : 0.0;
  // Every p_j first (vectorised), then their running sum alone: its adds are a chain, one
  // after the other for its bits, and nothing else waits in that loop.
  thread_local std::vector<double> p;
  if (p.size() < count) p.resize(count);
  choice_terms(choice.cdf.data(), count, scale, share / double(count), p.data());
  double cumulative = 0.0;
  for (size_t j = 0; j < count; ++j) {
    cumulative += p[j];
    choice.cdf[j] = float(cumulative);
  }
  choice.cdf[count - 1] = 1.0f;
  // Past 1, so the padding never counts as below a u_select in [0, 1).
  std::fill(choice.cdf.begin() + std::ptrdiff_t(count), choice.cdf.end(), 2.0f);
  choice.coarse.resize(padded / kChoiceBlock);
  for (size_t b = 0; b < choice.coarse.size(); ++b)
    choice.coarse[b] = choice.cdf[b * kChoiceBlock + kChoiceBlock - 1];
}

bool DirectLight::choice_fits(const Choice& choice, const ReceiverPoint& x, uint32_t mesh) {
  return choice.valid && choice.mesh == mesh && glm::dot(choice.normal, x.geometric_normal) > 0.9f;
}

DirectEstimate DirectLight::one_shadow_ray(const ReceiverPoint& x, const Choice& choice,
                                           float u_select, vec2 u_point) const {
  Ray shadow_ray;
  const DeferredEstimate deferred = sample_one_light(x, choice, u_select, u_point, shadow_ray);
  return traced(deferred, shadow_ray);
}

size_t DirectLight::chosen_light(const Choice& choice, float u_select) const {
  if (choice.lights <= 1) return 0;  // one light: always it
  // The first entry > u_select, std::upper_bound's answer on the CDF (non-decreasing), found by
  // counting the entries <= u_select: over the blocks' last entries, then inside the block
  // (both vectorise; a binary search is a chain of dependent loads), or, with many lights, by
  // a binary search without branches.
  const float* cdf = choice.cdf.data();
  size_t chosen = 0;
  if (choice.coarse.size() <= kChoiceMaxBlocks) {
    // 32-bit counts: four to an SSE register (size_t counts took two and their widening).
    const uint32_t blocks = uint32_t(choice.coarse.size());
    uint32_t block = 0;
    if (blocks > 1) {
      const float* coarse = choice.coarse.data();
      for (uint32_t b = 0; b < blocks; ++b) block += u_select < coarse[b] ? 0 : 1;
      block = std::min(block, blocks - 1);
    }
    const float* entries = cdf + size_t(block) * kChoiceBlock;
    uint32_t below = 0;
    for (size_t i = 0; i < kChoiceBlock; ++i) below += u_select < entries[i] ? 0 : 1;
    chosen = size_t(block) * kChoiceBlock + below;
  } else {
    chosen = partition_point_index(choice.cdf.size(),
                                   [&](size_t j) { return !(u_select < cdf[j]); });
  }
  return std::min(chosen, choice.lights - 1);
}

DeferredEstimate DirectLight::sample_one_light(const ReceiverPoint& x, const Choice& choice,
                                               float u_select, vec2 u_point, Ray& shadow_ray,
                                               size_t chosen) const {
  DeferredEstimate estimate;
  if (choice.lights == 0) return estimate;
  if (chosen == kNotChosen) chosen = chosen_light(choice, u_select);
  const float* cdf = choice.cdf.data();
  const float p = cdf[chosen] - (chosen > 0 ? cdf[chosen - 1] : 0.0f);
  if (!(p > 0.0f)) return estimate;
  estimate.light = int(chosen);
  vec3 f_over_pdf(0.0f);
  estimate.shadow_ray = unoccluded_contribution(x, chosen, u_point, f_over_pdf, shadow_ray);
  estimate.value = f_over_pdf / p;
  return estimate;
}

vec3 DirectLight::every_light(const ReceiverPoint& x, const vec2* u_points,
                              uint64_t& shadow_rays) const {
  vec3 sum(0.0f);
  for (size_t j = 0; j < light_count(); ++j) {
    bool traced = false;
    sum += contribution(x, j, u_points[j], traced);
    shadow_rays += traced ? 1 : 0;
  }
  return sum;
}

}  // namespace lb
