#include "bake/reference/light_tracer.h"

#include "bake/bsdf.h"
#include "bake/constants.h"

namespace lb::reference {

namespace {

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
  // Outside the rendered window (reference.h): no splat, and no connection ray to cast. The
  // random numbers drawn so far are the same either way, so later paths do not change.
  const PixelWindow window = render_window(context.params);
  const int x = std::min(int(lens.film.x), context.params.width - 1) - window.x;
  const int y = std::min(int(lens.film.y), context.params.height - 1) - window.y;
  if (x < 0 || y < 0 || x >= window.width || y >= window.height) return;
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
  splats.push_back({uint32_t(y) * uint32_t(window.width) + uint32_t(x), power * brdf * scale});
}

// A particle's diffuse bounce at `sp` (arriving along `incident`): a cosine-weighted direction
// about the shading normal on the side it came from, and the throughput times the adjoint
// BSDF's weight R |wo.ns| |wi.ng| / (|wo.ng| |wi.ns|) (Veach 1997, 5.3: shading normals are
// not symmetric; wo towards where the particle came from). False when the particle dies.
bool scatter_diffuse(const Scene& scene, const SurfacePoint& sp, vec3 incident, vec2 u,
                     vec3& throughput, Ray& ray) {
  const DiffuseFrame frame = diffuse_frame(scene, sp, incident);
  const vec3 wo = -incident;
  const float cos_wo_g = glm::dot(wo, frame.geometric_normal);
  const float cos_wo_s = glm::dot(wo, frame.shading_normal);
  const vec3 local = square_to_cosine_hemisphere(u);
  const vec3 wi = Frame(frame.shading_normal).to_world(local);
  const float cos_wi_g = glm::dot(wi, frame.geometric_normal);
  if (cos_wo_g <= 0.0f || cos_wo_s <= 0.0f || cos_wi_g <= 0.0f || !(local.z > 0.0f)) return false;
  throughput *= reflectance_at(scene, sp) * (cos_wo_s * cos_wi_g / (cos_wo_g * local.z));
  ray.origin = offset_ray_origin(sp.position, frame.geometric_normal, wi);
  ray.direction = wi;
  return true;
}

}  // namespace

void trace_light_paths(const Context& context, size_t count, double paths_in_pass, Rng& rng,
                       std::vector<Splat>& splats, ReferenceRays& rays) {
  const LightSet& lights = context.lights;
  if (lights.emitters_empty()) return;
  const Scene& scene = context.scene;
  const LightSources& sources = lights.sources();
  for (size_t path = 0; path < count; ++path) {
    ++rays.light_paths;
    const size_t j = lights.choose_emitter(rng.next_float());
    const vec2 u_origin = rng.next_2d();
    vec2 u_direction = rng.next_2d();
    vec3 emitted(0.0f);  // the power one path carries, W
    Ray ray;
    if (sources.kind(j) == LightKind::area) {
      const AreaLight& light = sources.area_light(j);
      const LightSample y = light.sample(scene, u_origin);
      const float side = light.pick_side(u_direction.x);  // a two-sided light: either side
      ray.direction = Frame(side * y.normal).to_world(square_to_cosine_hemisphere(u_direction));
      ray.origin = offset_ray_origin(y.position, y.normal, ray.direction);
      // L cos / (p_j (1/A_j) cos/pi), over one side's share 1/2 of a two-sided light's rays.
      emitted = light.radiance * (kPi * light.area / lights.emitter_probability(j));
      if (light.two_sided) emitted *= 2.0f;
    } else {
      // Lamps: from their point, or from the disk before the scene for a directional lamp.
      const EmittedRay e = sources.emit(j, u_origin, u_direction);
      ray.origin = e.origin;
      ray.direction = e.direction;
      emitted = e.power / lights.emitter_probability(j);
    }
    // A delta lamp's light whose first vertex is specular is light tracing's alone (no eye
    // path can reach the lamp through a specular vertex), after its first diffuse vertex too:
    // such a path goes on and is connected at every diffuse vertex. Other paths end there.
    const bool delta = sources.kind(j) != LightKind::area;
    bool first_specular = false;
    vec3 throughput(1.0f);  // relative to `emitted`
    for (int vertex = 0;; ++vertex) {
      ++rays.light;
      const std::optional<Hit> hit = context.accel.intersect(ray);
      if (!hit) break;
      // A lamp's range window fades its light by the distance to its first hit.
      if (vertex == 0) emitted *= sources.range_window(j, hit->t * glm::length(ray.direction));
      const SurfacePoint sp = surface_at(scene, *hit, ray);
      const Material& material = *sp.material;
      const vec3 incident = glm::normalize(ray.direction);
      if (vertex == 0) first_specular = !material.is_diffuse();
      if (material.is_diffuse()) {
        // L D ... belongs to the path tracer; L S+ D is connected here.
        if (!first_specular) break;
        connect_to_lens(context, sp, incident, emitted * throughput, paths_in_pass, rng, splats,
                        rays);
        if (!delta) break;
      }
      if (vertex >= context.params.max_depth) {
        ++rays.cut_at_max_depth;
        break;
      }
      if (material.is_diffuse()) {
        if (!scatter_diffuse(context.scene, sp, incident, rng.next_2d(), throughput, ray)) break;
      } else {
        const std::optional<SpecularScatter> scatter = scatter_specular(
            material, incident, specular_normal(scene, sp, incident), rng.next_2d());
        if (!scatter) break;
        throughput *= scatter->weight;
        ray.origin = offset_ray_origin(sp.position, sp.geometric_normal, scatter->direction);
        ray.direction = scatter->direction;
      }
      if (!survive_roulette(throughput, context.params.roulette_threshold, rng.next_float())) break;
      ray.tmin = 0.0f;
      ray.tmax = 1e30f;
    }
  }
}

}  // namespace lb::reference
