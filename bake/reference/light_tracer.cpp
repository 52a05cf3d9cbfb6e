#include "bake/reference/light_tracer.h"

#include <numbers>

#include "bake/bsdf.h"

namespace lb::reference {

namespace {

constexpr float kPi = std::numbers::pi_v<float>;

// The particle's contribution to the pixel that sees diffuse point `sp`: its power flux times
// the Lambertian BRDF, moved from surface area to film area by the camera's importance.
void connect_to_lens(const Context& context, const SurfacePoint& sp, vec3 arrival, vec3 power,
                     double paths_in_pass, Rng& rng, std::vector<Splat>& splats,
                     ReferenceRays& rays) {
  const DiffuseFrame frame = diffuse_frame(context.scene, sp, arrival);
  const vec3 wi = -arrival;  // towards where the particle came from
  const float cos_in_shading = glm::dot(wi, frame.shading_normal);
  const float cos_in_geometric = glm::dot(wi, frame.geometric_normal);
  if (cos_in_shading <= 0.0f || cos_in_geometric <= 0.0f) return;
  ThinLensCamera::Connection lens;
  if (!context.camera.connect(sp.position, rng.next_2d(), lens)) return;
  const vec3 to_lens = lens.lens_point - sp.position;
  const float d2 = glm::dot(to_lens, to_lens);
  if (!(d2 > 0.0f)) return;
  const vec3 wo = to_lens / std::sqrt(d2);
  const float cos_out = glm::dot(wo, frame.geometric_normal);
  if (cos_out <= 0.0f) return;  // the lens is on the other side: the surface is opaque
  ++rays.connection;
  if (context.accel.occluded(
          segment_ray(sp.position, frame.geometric_normal, lens.lens_point, -wo)))
    return;
  // The particles' flux per area is irradiance over the geometric normal; a shading normal
  // changes the cosine the BRDF sees (cos_in_shading / cos_in_geometric).
  const vec3 brdf = reflectance_at(context.scene, sp) * (1.0f / kPi);
  const float scale = float(
      double(cos_in_shading / cos_in_geometric * cos_out / d2 * lens.importance) / paths_in_pass);
  const int x = std::min(int(lens.film.x), context.params.width - 1);
  const int y = std::min(int(lens.film.y), context.params.height - 1);
  splats.push_back(
      {uint32_t(y) * uint32_t(context.params.width) + uint32_t(x), power * brdf * scale});
}

}  // namespace

void trace_light_paths(const Context& context, size_t count, double paths_in_pass, Rng& rng,
                       std::vector<Splat>& splats, ReferenceRays& rays) {
  const LightSet& lights = context.lights;
  if (lights.empty()) return;
  const Scene& scene = context.scene;
  for (size_t path = 0; path < count; ++path) {
    ++rays.light_paths;
    const size_t j = lights.choose(rng.next_float());
    const AreaLight& light = lights.lights()[j];
    const LightSample y = light.sample(scene, rng.next_2d());
    const vec3 direction = Frame(y.normal).to_world(square_to_cosine_hemisphere(rng.next_2d()));
    // L cos / (p_j (1/A_j) cos/pi): the power one path carries, W.
    const vec3 emitted = light.radiance * (kPi / lights.area_pdf(j));
    vec3 throughput(1.0f);  // through the specular chain
    Ray ray;
    ray.origin = offset_ray_origin(y.position, y.normal, direction);
    ray.direction = direction;
    for (int specular = 0;; ++specular) {
      ++rays.light;
      const std::optional<Hit> hit = context.accel.intersect(ray);
      if (!hit) break;
      const SurfacePoint sp = surface_at(scene, *hit, ray);
      const Material& material = *sp.material;
      const vec3 incident = glm::normalize(ray.direction);
      if (material.is_diffuse()) {
        // L D ... belongs to the path tracer; L S+ D is connected here and ends.
        if (specular > 0)
          connect_to_lens(context, sp, incident, emitted * throughput, paths_in_pass, rng, splats,
                          rays);
        break;
      }
      if (specular >= context.params.max_depth) {
        ++rays.cut_at_max_depth;
        break;
      }
      const std::optional<SpecularScatter> scatter =
          scatter_specular(material, incident, specular_normal(scene, sp, incident), rng.next_2d());
      if (!scatter) break;
      throughput *= scatter->weight;
      if (!survive_roulette(throughput, context.params.roulette_threshold, rng.next_float())) break;
      ray.origin = offset_ray_origin(sp.position, sp.geometric_normal, scatter->direction);
      ray.direction = scatter->direction;
      ray.tmin = 0.0f;
      ray.tmax = 1e30f;
    }
  }
}

}  // namespace lb::reference
