#include "bake/reference/path_tracer.h"

#include <numbers>

#include "bake/bsdf.h"

namespace lb::reference {

namespace {

constexpr float kInvPi = std::numbers::inv_pi_v<float>;

float power_heuristic(float a, float b) {
  const float a2 = a * a, b2 = b * b;
  return a2 + b2 > 0.0f ? a2 / (a2 + b2) : 0.0f;
}

// Next-event estimation at a diffuse vertex: one light by power, one point on it (area
// lights), its direction (the sky) or its exact place (lamps). Returns the MIS-weighted
// outgoing radiance per unit throughput (reflectance applied); delta lamps, which no scattered
// ray can hit, get weight 1.
vec3 next_event(const Context& context, vec3 position, const DiffuseFrame& frame, vec3 albedo,
                Rng& rng, ReferenceRays& rays) {
  const LightSet& lights = context.lights;
  if (lights.empty()) return vec3(0.0f);
  const size_t j = lights.choose(rng.next_float());
  const LightSources& sources = lights.sources();
  if (sources.kind(j) != LightKind::area) {
    const LightTowards t = sources.sample_towards(j, position, rng.next_2d());
    const float cos_shading = glm::dot(t.direction, frame.shading_normal);
    if (!(t.pdf > 0.0f) || cos_shading <= 0.0f ||
        glm::dot(t.direction, frame.geometric_normal) <= 0.0f)
      return vec3(0.0f);
    ++rays.shadow;
    if (context.accel.occluded(shadow_ray_towards(position, frame.geometric_normal, t)))
      return vec3(0.0f);
    const vec3 reflected = albedo * kInvPi * cos_shading * t.radiance;
    if (t.delta) return reflected / lights.probability(j);
    const float pdf_light = lights.probability(j) * t.pdf;  // per steradian
    return reflected * (power_heuristic(pdf_light, cos_shading * kInvPi) / pdf_light);
  }
  const AreaLight& light = sources.area_light(j);
  const LightSample y = light.sample(context.scene, rng.next_2d());
  const vec3 to_light = y.position - position;
  const float d2 = glm::dot(to_light, to_light);
  if (!(d2 > 0.0f)) return vec3(0.0f);
  const vec3 wi = to_light / std::sqrt(d2);
  const float cos_light = light.emitting_cosine(y.normal, -wi);
  const float cos_shading = glm::dot(wi, frame.shading_normal);
  if (cos_light <= 0.0f || cos_shading <= 0.0f || glm::dot(wi, frame.geometric_normal) <= 0.0f)
    return vec3(0.0f);
  ++rays.shadow;
  if (context.accel.occluded(segment_ray(position, frame.geometric_normal, y.position, y.normal)))
    return vec3(0.0f);
  const float pdf_light = lights.area_pdf(j) * d2 / cos_light;  // per steradian
  const float pdf_bsdf = cos_shading * kInvPi;
  return albedo * kInvPi * cos_shading * light.radiance *
         (power_heuristic(pdf_light, pdf_bsdf) / pdf_light);
}

// The sky seen along `direction` by a ray that left the scene: MIS-weighted against the sky's
// next-event estimate when the ray left a diffuse vertex.
vec3 escaped(const Context& context, vec3 direction, bool from_diffuse, float pdf_bsdf) {
  const SkyLight* sky = context.lights.sources().sky();
  if (!sky) return vec3(0.0f);
  float weight = 1.0f;
  if (from_diffuse) {
    const float pdf_light =
        context.lights.probability(size_t(context.lights.sky())) * sky->pdf(direction);
    weight = power_heuristic(pdf_bsdf, pdf_light);
  }
  return sky->radiance(direction) * weight;
}

}  // namespace

vec3 trace_eye_path(const Context& context, const Ray& primary, Rng& rng, ReferenceRays& rays) {
  const Scene& scene = context.scene;
  const ReferenceParams& params = context.params;
  const bool direct_only = params.terms == Terms::direct;
  vec3 radiance(0.0f), throughput(1.0f);
  Ray ray = primary;
  // What came before the current vertex, for the partition and the MIS weights.
  enum class Previous { lens, diffuse, specular } previous = Previous::lens;
  float previous_pdf_bsdf = 0.0f;  // solid-angle pdf of the ray leaving a diffuse vertex
  int diffuse_vertices = 0;
  bool first_vertex_diffuse = false;

  for (int depth = 0;; ++depth) {
    ++(depth == 0 ? rays.camera : rays.bounce);
    const std::optional<Hit> hit = context.accel.intersect(ray);
    const vec3 direction = glm::normalize(ray.direction);
    if (!hit) {
      // The sky: found by the path tracer alone after specular vertices (E D S+ sky as well;
      // light tracing does not start from the sky).
      radiance += throughput *
                  escaped(context, direction, previous == Previous::diffuse, previous_pdf_bsdf);
      break;
    }
    const SurfacePoint sp = surface_at(scene, *hit, ray);
    const Material& material = *sp.material;
    float cos_arrival = -glm::dot(direction, sp.geometric_normal);
    if (material.two_sided_emission) cos_arrival = std::abs(cos_arrival);

    if (material.is_emitter() && cos_arrival > 0.0f) {
      float weight = 1.0f;
      if (previous == Previous::diffuse) {
        const int j = context.lights.light_of_mesh(hit->mesh);
        if (j >= 0) {
          const float distance = hit->t * glm::length(ray.direction);
          const float pdf_light =
              context.lights.area_pdf(size_t(j)) * distance * distance / cos_arrival;
          weight = power_heuristic(previous_pdf_bsdf, pdf_light);
        }
      } else if (previous == Previous::specular && diffuse_vertices == 1 && first_vertex_diffuse &&
                 params.light_tracing) {
        weight = 0.0f;  // E D S+ L: a caustic seen directly, the light tracer's path
      }
      radiance += throughput * material.emission * weight;
    }
    // Direct only: nothing after the first diffuse vertex's light (NEE + its scattered ray).
    if (direct_only && diffuse_vertices > 0) break;
    if (depth >= params.max_depth) {
      ++rays.cut_at_max_depth;
      break;
    }

    if (material.is_diffuse()) {
      const DiffuseFrame frame = diffuse_frame(scene, sp, direction);
      const vec3 albedo = reflectance_at(scene, sp);
      if (++diffuse_vertices == 1) first_vertex_diffuse = previous == Previous::lens;
      radiance += throughput * next_event(context, sp.position, frame, albedo, rng, rays);
      const vec3 local = square_to_cosine_hemisphere(rng.next_2d());
      const vec3 wi = Frame(frame.shading_normal).to_world(local);
      if (glm::dot(wi, frame.geometric_normal) <= 0.0f) break;  // the BSDF is 0 below the surface
      throughput *= albedo;  // f cos / pdf = (R / pi) cos / (cos / pi)
      previous = Previous::diffuse;
      previous_pdf_bsdf = local.z * kInvPi;
      ray.origin = offset_ray_origin(sp.position, frame.geometric_normal, wi);
      ray.direction = wi;
    } else {
      const std::optional<SpecularScatter> scatter = scatter_specular(
          material, direction, specular_normal(scene, sp, direction), rng.next_2d());
      if (!scatter) break;
      throughput *= scatter->weight;
      previous = Previous::specular;
      ray.origin = offset_ray_origin(sp.position, sp.geometric_normal, scatter->direction);
      ray.direction = scatter->direction;
    }
    ray.tmin = 0.0f;
    ray.tmax = 1e30f;
    if (!survive_roulette(throughput, params.roulette_threshold, rng.next_float())) break;
  }
  return radiance;
}

}  // namespace lb::reference
