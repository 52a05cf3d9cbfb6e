#include "bake/hq/hq_render.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <mutex>
#include <stdexcept>
#include <string>

#include "bake/bsdf.h"
#include "bake/bump.h"
#include "bake/transport/baked_terms.h"
#include "bake/surface.h"
#include "bake/thin_lens_camera.h"
#include "bake/work_limits.h"

namespace lb {

std::vector<vec3> Film::average() const {
  std::vector<vec3> image(sum.size(), vec3(0.0f));
  if (samples_per_pixel == 0) return image;
  const float scale = 1.0f / float(samples_per_pixel);
  for (size_t i = 0; i < sum.size(); ++i) image[i] = sum[i] * scale;
  return image;
}

void check_hq_params(const HqParams& params) {
  const std::string size = std::to_string(params.width) + "x" + std::to_string(params.height);
  if (params.width < 1 || params.height < 1 || params.width > 16384 || params.height > 16384)
    throw std::invalid_argument("render: size " + size + ": each side must be in [1, 16384]");
  const int64_t spp = int64_t(params.samples_per_side) * params.samples_per_side;
  if (params.final_gather < 0 || params.final_gather > kMaxFinalGather)
    throw std::invalid_argument("render: --final-gather " + std::to_string(params.final_gather) +
                                " is outside [0, " + std::to_string(kMaxFinalGather) + "]");
  if (params.samples_per_side < 1 || spp > kMaxSamplesPerPixel)
    throw std::invalid_argument("render: " + std::to_string(spp) +
                                " samples per pixel per pass is outside [1, " +
                                std::to_string(kMaxSamplesPerPixel) + "]: use more passes");
  if (params.shard_count < 1 || params.shard_count > kMaxShards || params.shard < 0 ||
      params.shard >= params.shard_count)
    throw std::invalid_argument("render: shard " + std::to_string(params.shard) + "/" +
                                std::to_string(params.shard_count) +
                                " needs 0 <= i < n <= " + std::to_string(kMaxShards));
  // The film's sum, one pass's sum, the average, the image and the writer's copy: 5 RGB floats.
  require_memory("render: size " + size + ", which",
                 double(params.width) * double(params.height) * 5.0 * sizeof(vec3));
}

int hq_tile_of_pixel(int x, int y, int width, int tile_size) {
  const int tiles_x = (width + tile_size - 1) / tile_size;
  return (y / tile_size) * tiles_x + x / tile_size;
}

HqRenderer::HqRenderer(const BakedScene& baked, const HqParams& params)
    : baked_(baked), params_(params) {
  check_hq_params(params);
  params_.samples_per_side = std::max(params_.samples_per_side, 1);
  params_.tile_size = std::max(params_.tile_size, 1);
  params_.max_wave_paths = std::max(params_.max_wave_paths, 1);
  // A gathering path costs about 1 + final_gather times a plain one: fewer paths a wave keep
  // a wave's time, and so progress and Ctrl-C, as without the gather (bits as for any wave size).
  params_.max_wave_paths = std::max(params_.max_wave_paths / (1 + params_.final_gather), 1);
  params_.max_depth = std::max(params_.max_depth, 0);
  accel_ = std::make_unique<Accel>(baked_.scene);
  direct_ = std::make_unique<DirectLight>(baked_.scene, *accel_);
  gather_ = std::make_unique<GatherContext>(GatherContext{baked_, *accel_, *direct_});
  gather_->max_specular_depth = params_.max_depth;
}

HqRenderer::~HqRenderer() = default;

// ---- one viewing path ------------------------------------------------------------------

bool HqRenderer::advance(const std::optional<Hit>& hit, const Ray& ray, const PathSamples& samples,
                         Rng& rng, Path& path, Ray& next, DeferredEstimate& shadow, Ray& shadow_ray,
                         HqRayCounts& counts) const {
  shadow.shadow_ray = false;
  if (!hit) {
    // Camera rays and specular paths that leave the scene see the sky (diffuse surfaces get
    // its light from the bake, as soft light).
    if (const SkyLight* sky = direct_->sky())
      path.radiance += path.throughput * sky->radiance(glm::normalize(ray.direction));
    return false;
  }
  // The light the pixel's choice gives this sample, found before the hit is shaded so the
  // light's data loads beside the shading (the choice is redone, and so the light, at a hit it
  // does not fit).
  size_t chosen = DirectLight::kNotChosen;
  const bool reuse = params_.direct && params_.reuse_light_choice && samples.choice;
  if (reuse && samples.choice->valid && samples.choice->lights > 1) {
    chosen = direct_->chosen_light(*samples.choice, samples.light_select);
    direct_->prefetch_light(chosen);
  }
  const Scene& scene = baked_.scene;
  const SurfacePoint sp = surface_at(scene, *hit, ray);
  const Material& material = *sp.material;
  const vec3 direction = glm::normalize(ray.direction);
  const bool front = glm::dot(direction, sp.geometric_normal) < 0.0f;
  if (material.is_emitter() && (front || material.two_sided_emission)) path.radiance += path.throughput * material.emission;

  if (material.is_diffuse()) {
    // Diffuse surfaces are two-sided for direct light: normals face the viewer's side.
    const ReceiverPoint x = receiver_at(scene, sp, direction);
    if (params_.direct) {
      if (reuse) {
        if (!DirectLight::choice_fits(*samples.choice, x, sp.mesh)) {
          direct_->prepare_choice(x, sp.mesh, *samples.choice);
          chosen = DirectLight::kNotChosen;
        }
        shadow = direct_->sample_one_light(x, *samples.choice, samples.light_select,
                                           samples.light_point, shadow_ray, chosen);
      } else {
        shadow =
            direct_->sample_one_light(x, samples.light_select, samples.light_point, shadow_ray);
      }
    }
    vec3 baked(0.0f);  // E/pi: illumination map + vertex radiosity
    if (params_.illumination_map) baked += illumination_at(baked_, sp);
    if (params_.radiosity && params_.final_gather > 0) {
      GatherCounts gathered;
      baked += gather_soft_light(*gather_, x, samples.gather_stream, params_.final_gather,
                                 samples.gather_strata, &gathered);
      counts.gather += gathered.rays;
      counts.gather_shadow += gathered.shadow;
    } else if (params_.radiosity) {
      baked += soft_light_at(baked_, sp);
    }
    const vec3 weight = path.throughput * reflectance_at(scene, sp);
    path.radiance += weight * baked;
    shadow.value *= weight;
    return false;
  }

  const int bounce = path.specular_bounces++;
  const vec2 u = bounce < samples.stratified_bounces ? samples.specular[bounce] : rng.next_2d();
  const std::optional<SpecularScatter> scatter =
      scatter_specular(material, direction, specular_normal(scene, sp, direction), u);
  if (!scatter) return false;
  path.throughput *= scatter->weight;
  // Russian roulette below the cut-off keeps the estimate unbiased while ending weak paths.
  if (!survive_roulette(path.throughput, params_.throughput_cutoff, rng)) return false;
  next.origin = offset_ray_origin(sp.position, sp.geometric_normal, scatter->direction);
  next.direction = scatter->direction;
  next.tmin = 0.0f;
  next.tmax = 1e30f;
  return true;
}

vec3 HqRenderer::trace(const Ray& primary, const PathSamples& samples, Rng& rng,
                       HqRayCounts& counts) const {
  Path path;
  Ray ray = primary;
  for (int depth = 0; depth <= params_.max_depth; ++depth) {
    ++counts.viewing;
    DeferredEstimate shadow;
    Ray next, shadow_ray;
    const bool more =
        advance(accel_->intersect(ray), ray, samples, rng, path, next, shadow, shadow_ray, counts);
    if (shadow.shadow_ray) {
      ++counts.shadow;
      if (!accel_->occluded(shadow_ray)) path.radiance += shadow.value;
    }
    if (!more) break;
    ray = next;
  }
  return path.radiance;
}

void HqRenderer::render_pass(const Camera& camera, Film& film, HqStats& stats,
                             const Progress& progress) const {
  const auto start = std::chrono::steady_clock::now();
  if (film.width != params_.width || film.height != params_.height)
    film = Film(params_.width, params_.height);
  const ThinLensCamera lens_camera(camera, params_.width, params_.height);
  const int tiles_x = (params_.width + params_.tile_size - 1) / params_.tile_size;
  const int tiles_y = (params_.height + params_.tile_size - 1) / params_.tile_size;
  std::vector<int> tiles;  // this shard's
  uint64_t pixels = 0;
  for (int tile = 0; tile < tiles_x * tiles_y; ++tile) {
    if (hq_shard_of_tile(tile, params_.shard_count) != params_.shard) continue;
    tiles.push_back(tile);
    const int x0 = (tile % tiles_x) * params_.tile_size, y0 = (tile / tiles_x) * params_.tile_size;
    pixels += uint64_t(std::min(params_.tile_size, params_.width - x0)) *
              uint64_t(std::min(params_.tile_size, params_.height - y0));
  }
  const int pass = film.passes;

  std::vector<vec3> pass_sum(film.sum.size(), vec3(0.0f));
  std::atomic<uint64_t> viewing{0}, shadow{0}, samples{0}, gather{0}, gather_shadow{0};
  // Progress by paths, so a pass of few tiles and many samples still reports as it goes.
  const uint64_t paths_total = std::max<uint64_t>(
      pixels * uint64_t(params_.samples_per_side) * uint64_t(params_.samples_per_side), 1);
  std::atomic<uint64_t> paths_done{0};
  std::atomic<int> percent_reported{-1};
  std::mutex report_mutex;
  const std::function<bool(uint64_t)> wave_done = [&](uint64_t paths) {
    const uint64_t done = paths_done += paths;
    const int percent = int(100 * done / paths_total);
    if (progress.report && percent > percent_reported) {
      std::lock_guard<std::mutex> lock(report_mutex);
      if (percent > percent_reported) {
        percent_reported = percent;
        progress.update("render", double(done) / double(paths_total));
      }
    }
    return !progress.cancelled();
  };
  tbb::parallel_for(tbb::blocked_range<size_t>(0, tiles.size(), 1),
                    [&](const tbb::blocked_range<size_t>& range) {
                      for (size_t t = range.begin(); t != range.end(); ++t) {
                        if (progress.cancelled()) return;
                        HqRayCounts counts;
                        render_tile(lens_camera, tiles[t], pass, pass_sum, counts, wave_done);
                        viewing += counts.viewing;
                        shadow += counts.shadow;
                        samples += counts.samples;
                        gather += counts.gather;
                        gather_shadow += counts.gather_shadow;
                      }
                    });
  progress.throw_if_cancelled();

  for (size_t i = 0; i < film.sum.size(); ++i) film.sum[i] += pass_sum[i];
  film.samples_per_pixel += uint64_t(params_.samples_per_side) * uint64_t(params_.samples_per_side);
  ++film.passes;
  stats.rays.viewing += viewing;
  stats.rays.shadow += shadow;
  stats.rays.samples += samples;
  stats.rays.gather += gather;
  stats.rays.gather_shadow += gather_shadow;
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
