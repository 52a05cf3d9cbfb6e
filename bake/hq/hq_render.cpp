#include "bake/hq/hq_render.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <mutex>
#include <numeric>

#include "bake/bsdf.h"
#include "bake/hq/baked_terms.h"
#include "bake/hq/bump.h"
#include "bake/hq/camera.h"
#include "bake/surface.h"

namespace lb {

std::vector<vec3> Film::average() const {
  std::vector<vec3> image(sum.size(), vec3(0.0f));
  if (samples_per_pixel == 0) return image;
  const float scale = 1.0f / float(samples_per_pixel);
  for (size_t i = 0; i < sum.size(); ++i) image[i] = sum[i] * scale;
  return image;
}

HqRenderer::HqRenderer(const BakedScene& baked, const HqParams& params)
    : baked_(baked), params_(params) {
  params_.samples_per_side = std::max(params_.samples_per_side, 1);
  params_.tile_size = std::max(params_.tile_size, 1);
  params_.max_depth = std::max(params_.max_depth, 0);
  accel_ = std::make_unique<Accel>(baked_.scene);
  direct_ = std::make_unique<DirectLight>(baked_.scene, *accel_);
}

HqRenderer::~HqRenderer() = default;

// ---- one viewing path ------------------------------------------------------------------

vec3 HqRenderer::trace(const Ray& primary, const PathSamples& samples, Rng& rng,
                       HqRayCounts& counts) const {
  const Scene& scene = baked_.scene;
  vec3 radiance(0.0f);
  vec3 throughput(1.0f);
  Ray ray = primary;
  for (int depth = 0; depth <= params_.max_depth; ++depth) {
    ++counts.viewing;
    const std::optional<Hit> hit = accel_->intersect(ray);
    if (!hit) break;
    const SurfacePoint sp = surface_at(scene, *hit, ray);
    const Material& material = *sp.material;
    const vec3 direction = glm::normalize(ray.direction);
    const bool front = glm::dot(direction, sp.geometric_normal) < 0.0f;
    if (material.is_emitter() && front) radiance += throughput * material.emission;

    if (material.is_diffuse()) {
      // Diffuse surfaces are two-sided for direct light: normals face the viewer's side.
      const float side = front ? 1.0f : -1.0f;
      ReceiverPoint x;
      x.position = sp.position;
      x.geometric_normal = side * sp.geometric_normal;
      x.shading_normal = side * bumped_normal(scene, sp);
      if (glm::dot(x.shading_normal, x.geometric_normal) <= 0.0f)
        x.shading_normal = x.geometric_normal;
      vec3 incident(0.0f);  // E/pi: direct + illumination map + vertex radiosity
      if (params_.direct) {
        DirectEstimate direct;
        if (params_.reuse_light_choice && samples.choice) {
          if (!DirectLight::choice_fits(*samples.choice, x, sp.mesh))
            direct_->prepare_choice(x, sp.mesh, *samples.choice);
          direct = direct_->one_shadow_ray(x, *samples.choice, samples.light_select,
                                           samples.light_point);
        } else {
          direct = direct_->one_shadow_ray(x, samples.light_select, samples.light_point);
        }
        counts.shadow += direct.shadow_ray ? 1 : 0;
        incident += direct.value;
      }
      if (params_.illumination_map) incident += illumination_at(baked_, sp);
      if (params_.radiosity) incident += vertex_radiosity_at(baked_, sp);
      radiance += throughput * reflectance_at(scene, sp) * incident;
      break;
    }

    const std::optional<SpecularScatter> scatter =
        scatter_specular(material, direction, bumped_normal(scene, sp), rng.next_2d());
    if (!scatter) break;
    throughput *= scatter->weight;
    // Russian roulette below the cut-off keeps the estimate unbiased while ending weak paths.
    const float strength = std::max({throughput.x, throughput.y, throughput.z});
    if (!(strength > 0.0f)) break;
    if (strength < params_.throughput_cutoff) {
      const float survive = strength / params_.throughput_cutoff;
      if (rng.next_float() >= survive) break;
      throughput /= survive;
    }
    ray.origin = offset_ray_origin(sp.position, sp.geometric_normal, scatter->direction);
    ray.direction = scatter->direction;
    ray.tmin = 0.0f;
    ray.tmax = 1e30f;
  }
  return radiance;
}

// ---- pixels and tiles --------------------------------------------------------------------

namespace {

void shuffle(std::vector<int>& values, Rng& rng) {
  for (size_t i = values.size(); i > 1; --i) {
    const size_t j = size_t(rng.next_u32() % uint32_t(i));
    std::swap(values[i - 1], values[j]);
  }
}

}  // namespace

void HqRenderer::render_tile(const ThinLensCamera& camera, int tile, int pass,
                             std::vector<vec3>& out, HqRayCounts& counts) const {
  const int n = params_.samples_per_side;
  const int count = n * n;
  const int tiles_x = (params_.width + params_.tile_size - 1) / params_.tile_size;
  const int x0 = (tile % tiles_x) * params_.tile_size;
  const int y0 = (tile / tiles_x) * params_.tile_size;
  const int x1 = std::min(x0 + params_.tile_size, params_.width);
  const int y1 = std::min(y0 + params_.tile_size, params_.height);
  // Uncorrelated jittering (Cook 1986): the lens, light-point and light-choice strata are
  // assigned to the pixel strata through independent random permutations.
  const size_t strata = size_t(count);
  std::vector<int> lens_order(strata), point_order(strata), select_order(strata);
  DirectLight::Choice choice;
  for (int y = y0; y < y1; ++y) {
    for (int x = x0; x < x1; ++x) {
      const uint64_t pixel = uint64_t(y) * uint64_t(params_.width) + uint64_t(x);
      Rng rng(hash_seed(params_.seed, uint64_t(pass), pixel));
      std::iota(lens_order.begin(), lens_order.end(), 0);
      std::iota(point_order.begin(), point_order.end(), 0);
      std::iota(select_order.begin(), select_order.end(), 0);
      shuffle(lens_order, rng);
      shuffle(point_order, rng);
      shuffle(select_order, rng);
      vec3 sum(0.0f);
      choice.valid = false;  // a pixel's choice never leaks into the next (determinism)
      for (int s = 0; s < count; ++s) {
        const vec2 film = vec2(float(x), float(y)) + stratified(s % n, s / n, n, n, rng.next_2d());
        const int lens_stratum = lens_order[size_t(s)];
        const vec2 lens = stratified(lens_stratum % n, lens_stratum / n, n, n, rng.next_2d());
        const int point_stratum = point_order[size_t(s)];
        PathSamples samples;
        samples.light_point = stratified(point_stratum % n, point_stratum / n, n, n, rng.next_2d());
        samples.light_select = (float(select_order[size_t(s)]) + rng.next_float()) / float(count);
        samples.light_point = glm::min(samples.light_point, vec2(0.99999994f));
        samples.choice = &choice;
        sum += trace(camera.generate(film, lens), samples, rng, counts);
      }
      counts.samples += uint64_t(count);
      out[size_t(pixel)] = sum;
    }
  }
}

void HqRenderer::render_pass(const Camera& camera, Film& film, HqStats& stats,
                             const Progress& progress) const {
  const auto start = std::chrono::steady_clock::now();
  if (film.width != params_.width || film.height != params_.height)
    film = Film(params_.width, params_.height);
  const ThinLensCamera lens_camera(camera, params_.width, params_.height);
  const int tiles_x = (params_.width + params_.tile_size - 1) / params_.tile_size;
  const int tiles_y = (params_.height + params_.tile_size - 1) / params_.tile_size;
  const int tiles = tiles_x * tiles_y;
  const int pass = film.passes;

  std::vector<vec3> pass_sum(film.sum.size(), vec3(0.0f));
  std::atomic<uint64_t> viewing{0}, shadow{0}, samples{0};
  std::atomic<int> tiles_done{0};
  std::mutex report_mutex;
  tbb::parallel_for(tbb::blocked_range<int>(0, tiles, 1),
                    [&](const tbb::blocked_range<int>& range) {
                      for (int tile = range.begin(); tile != range.end(); ++tile) {
                        if (progress.cancelled()) return;
                        HqRayCounts counts;
                        render_tile(lens_camera, tile, pass, pass_sum, counts);
                        viewing += counts.viewing;
                        shadow += counts.shadow;
                        samples += counts.samples;
                        const int done = ++tiles_done;
                        if (progress.report && (done % 16 == 0 || done == tiles)) {
                          std::lock_guard<std::mutex> lock(report_mutex);
                          progress.update("render", double(done) / double(tiles));
                        }
                      }
                    });
  progress.throw_if_cancelled();

  for (size_t i = 0; i < film.sum.size(); ++i) film.sum[i] += pass_sum[i];
  film.samples_per_pixel += uint64_t(params_.samples_per_side) * uint64_t(params_.samples_per_side);
  ++film.passes;
  stats.rays.viewing += viewing;
  stats.rays.shadow += shadow;
  stats.rays.samples += samples;
  stats.pass_seconds.push_back(
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
}

std::vector<vec3> HqRenderer::render(const Camera& camera, int passes, HqStats& stats,
                                     const Progress& progress) const {
  Film film(params_.width, params_.height);
  for (int pass = 0; pass < std::max(passes, 1); ++pass) render_pass(camera, film, stats, progress);
  return film.average();
}

}  // namespace lb
