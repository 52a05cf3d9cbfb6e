#include "bake/reference/reference.h"

#include <sys/resource.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>
#include <stdexcept>
#include <string>
#include <string_view>

#include "bake/reference/light_set.h"
#include "bake/reference/light_tracer.h"
#include "bake/reference/path_tracer.h"
#include "bake/thin_lens_camera.h"

namespace lb::reference {

namespace {

// Eye paths and light blocks draw from streams far from any pixel index, so a reference and
// an HQ render with the same seed (HQ draws from hash_seed(seed, pass, pixel)) are
// independent: their difference then shows their combined noise, not less.
constexpr uint64_t kEyeStream = uint64_t(1) << 41;
constexpr uint64_t kLightStream = uint64_t(1) << 40;

double cpu_seconds_now() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  auto seconds = [](timeval t) { return double(t.tv_sec) + 1e-6 * double(t.tv_usec); };
  return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

// Rays counted per tile or block, added to the shared totals once.
struct AtomicRays {
  std::atomic<uint64_t> camera{0}, bounce{0}, shadow{0}, light{0}, connection{0}, eye_paths{0},
      light_paths{0}, cut_at_max_depth{0};
  void add(const ReferenceRays& r) {
    camera += r.camera, bounce += r.bounce, shadow += r.shadow, light += r.light;
    connection += r.connection, eye_paths += r.eye_paths, light_paths += r.light_paths;
    cut_at_max_depth += r.cut_at_max_depth;
  }
  void into(ReferenceRays& r) const {
    r.camera += camera, r.bounce += bounce, r.shadow += shadow, r.light += light;
    r.connection += connection, r.eye_paths += eye_paths, r.light_paths += light_paths;
    r.cut_at_max_depth += cut_at_max_depth;
  }
};

}  // namespace

void check_reference_params(const ReferenceParams& p) {
  auto require = [](bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument("reference: " + what);
  };
  require(p.width >= 1 && p.height >= 1 && p.width <= 16384 && p.height <= 16384,
          "width and height must be in [1, 16384]");
  require(p.spp >= 1, "spp must be at least 1");
  require(p.time_limit_seconds >= 0.0 && std::isfinite(p.time_limit_seconds),
          "time limit must be >= 0 seconds");
  require(p.light_paths_per_pixel >= 0.0 && p.light_paths_per_pixel <= 1024.0,
          "light paths per pixel must be in [0, 1024]");
  require(p.roulette_threshold > 0.0f && p.roulette_threshold <= 1.0f,
          "roulette threshold must be in (0, 1]");
  require(p.max_depth >= 1, "max depth must be at least 1");
  require(p.tile_size >= 1 && p.light_block_size >= 1, "tile and block sizes must be positive");
  require(p.shard_count >= 1 && p.shard >= 0 && p.shard < p.shard_count,
          "shard must be in [0, shard count)");
  require(p.shard_count == 1 || p.time_limit_seconds == 0.0,
          "a time limit and shards exclude each other (each shard's pass count would depend on "
          "its machine's clock)");
  const PixelWindow& w = p.window;
  require(w.empty() || (w.width >= 1 && w.height >= 1 && w.x >= 0 && w.y >= 0 &&
                        w.x <= p.width - w.width && w.y <= p.height - w.height),
          "window must be non-empty and inside the " + std::to_string(p.width) + "x" +
              std::to_string(p.height) + " image");
}

PixelWindow render_window(const ReferenceParams& p) {
  return p.window.empty() ? PixelWindow{0, 0, p.width, p.height} : p.window;
}

std::vector<vec3> window_in_image(const std::vector<vec3>& window_pixels,
                                  const ReferenceParams& p) {
  const PixelWindow w = render_window(p);
  if (w.width == p.width && w.height == p.height) return window_pixels;
  std::vector<vec3> image(size_t(p.width) * size_t(p.height), vec3(0.0f));
  for (int y = 0; y < w.height; ++y)
    std::copy_n(window_pixels.begin() + std::ptrdiff_t(y) * w.width, w.width,
                image.begin() + (std::ptrdiff_t(w.y + y) * p.width + w.x));
  return image;
}

int shard_passes(const ReferenceParams& p) {
  return p.shard >= p.spp ? 0 : (p.spp - p.shard + p.shard_count - 1) / p.shard_count;
}

struct ReferenceRenderer::Impl {
  Impl(const Scene& scene, const Accel& accel, const Camera& camera, const ReferenceParams& params)
      : lens(camera, params.width, params.height),
        lights(scene),
        context{scene, accel, lens, lights, params} {}
  ThinLensCamera lens;
  LightSet lights;
  Context context;
};

ReferenceRenderer::ReferenceRenderer(const Scene& scene, const Accel& accel, const Camera& camera,
                                     const ReferenceParams& params)
    : params_(params) {
  check_reference_params(params_);
  impl_ = std::make_unique<Impl>(scene, accel, camera, params_);
}

ReferenceRenderer::~ReferenceRenderer() = default;

void ReferenceRenderer::render_pass(Film& film, uint64_t pass, ReferenceStats& stats,
                                    const Progress& progress) const {
  const auto start = std::chrono::steady_clock::now();
  const double cpu_start = cpu_seconds_now();
  const Context& context = impl_->context;
  const int width = params_.width, height = params_.height, tile = params_.tile_size;
  const PixelWindow window = render_window(params_);
  if (film.width != window.width || film.height != window.height)
    film = Film(window.width, window.height);
  const double passes_to_do = std::max(1, shard_passes(params_));

  // Tiles over the window; light paths as many as the whole image's (same bits in the window).
  const int tiles_x = (window.width + tile - 1) / tile, tiles_y = (window.height + tile - 1) / tile;
  const int tiles = tiles_x * tiles_y;
  const bool light_tracing =
      params_.terms == Terms::all && params_.light_tracing && params_.light_paths_per_pixel > 0.0;
  const double light_paths =
      light_tracing ? std::ceil(params_.light_paths_per_pixel * double(width) * double(height)) : 0;
  const size_t block_size = size_t(params_.light_block_size);
  const size_t blocks = (size_t(light_paths) + block_size - 1) / block_size;
  const size_t work = size_t(tiles) + blocks;

  std::vector<vec3> estimate(size_t(window.width) * size_t(window.height), vec3(0.0f));
  std::vector<std::vector<Splat>> block_splats(blocks);
  AtomicRays counted;
  std::atomic<size_t> done{0};
  std::mutex report_mutex;
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, work, 1), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t item = r.begin(); item != r.end(); ++item) {
          if (progress.cancelled()) return;
          ReferenceRays rays;
          if (item < size_t(tiles)) {
            const int tx = int(item) % tiles_x, ty = int(item) / tiles_x;
            for (int wy = ty * tile; wy < std::min(window.height, (ty + 1) * tile); ++wy)
              for (int wx = tx * tile; wx < std::min(window.width, (tx + 1) * tile); ++wx) {
                const int x = window.x + wx, y = window.y + wy;
                // The stream of the pixel's index in the whole image, window or not.
                Rng rng(hash_seed(params_.seed, pass,
                                  kEyeStream + size_t(y) * size_t(width) + size_t(x)));
                const vec2 film_point = vec2(float(x), float(y)) + rng.next_2d();
                const Ray ray = impl_->lens.generate(film_point, rng.next_2d());
                ++rays.eye_paths;
                const vec3 value = trace_eye_path(context, ray, rng, rays);
                // A NaN or infinity would poison the pixel for good; count it as a lost sample.
                estimate[size_t(wy) * size_t(window.width) + size_t(wx)] =
                    std::isfinite(value.x + value.y + value.z) ? value : vec3(0.0f);
              }
          } else {
            const size_t block = item - size_t(tiles);
            const size_t first = block * block_size;
            const size_t count = std::min(block_size, size_t(light_paths) - first);
            Rng rng(hash_seed(params_.seed, pass, kLightStream + block));
            trace_light_paths(context, count, light_paths, rng, block_splats[block], rays);
          }
          counted.add(rays);
          const size_t finished = ++done;
          if (progress.report && (finished % 16 == 0 || finished == work)) {
            std::lock_guard<std::mutex> lock(report_mutex);
            progress.update("reference", (double(film.passes()) + double(finished) / double(work)) /
                                             passes_to_do);
          }
        }
      });
  progress.throw_if_cancelled();

  // Splats in block order: the sum's rounding does not depend on which thread ran a block.
  for (const std::vector<Splat>& splats : block_splats)
    for (const Splat& s : splats)
      if (std::isfinite(s.value.x + s.value.y + s.value.z)) estimate[s.pixel] += s.value;
  film.add_pass(pass, estimate);
  counted.into(stats.rays);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  stats.pass_seconds.push_back(seconds);
  stats.wall_seconds += seconds;
  stats.cpu_seconds += cpu_seconds_now() - cpu_start;
}

Film ReferenceRenderer::render(ReferenceStats& stats, const Progress& progress) const {
  Film film(params_.width, params_.height);
  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  const double limit = params_.time_limit_seconds;
  // With a time limit, whichever of the spp count and the clock is nearer its end is shown.
  Progress timed = progress;
  if (limit > 0.0 && progress.report)
    timed.report = [&](std::string_view stage, double fraction) {
      progress.update(stage, std::min(1.0, std::max(fraction, elapsed() / limit)));
    };
  for (int pass = params_.shard; pass < params_.spp; pass += params_.shard_count) {
    render_pass(film, uint64_t(pass), stats, timed);
    if (limit > 0.0 && elapsed() >= limit) break;
  }
  return film;
}

}  // namespace lb::reference
