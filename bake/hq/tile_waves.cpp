// HqRenderer::render_tile: a tile's viewing paths advance one bounce at a time, and each
// bounce's rays go to Embree as one wave through the stream API (Accel::intersect_many,
// Accel::occluded_many): the primaries of neighbouring pixels are coherent, so Embree traces
// them as packets. Every path draws from its own pixel's random numbers and each pixel sums its
// samples in sample order, so the image has the same bits whatever the thread count.

#include <algorithm>
#include <memory>
#include <numeric>

#include "bake/hq/hq_render.h"
#include "bake/sobol_points.h"
#include "bake/thin_lens_camera.h"

namespace lb {

namespace {

// Pixels per wave: 64 pixels x 16 spp = 1024 paths, many of Embree's 64-ray chunks per wave,
// ~150 KB of per-thread buffers. A wave never holds more than HqParams::max_wave_paths paths:
// at high sample counts it takes fewer pixels, and past that a pixel's samples are cut into
// chunks (in sample order, so the pixel's numbers and its sum are drawn the same way).
constexpr int kWavePixels = 64;

void shuffle(std::vector<int>& values, Rng& rng) {
  for (size_t i = values.size(); i > 1; --i) {
    const size_t j = size_t(rng.next_u32() % uint32_t(i));
    std::swap(values[i - 1], values[j]);
  }
}

// Per-thread buffers of one wave of paths, reused from tile to tile (no allocation per tile).
struct WaveBuffers {
  std::vector<PathSamples> samples;          // per path
  std::vector<Rng> rngs;                     // per path: its specular bounces
  std::vector<DirectLight::Choice> choices;  // per pixel
  std::vector<Ray> rays;                     // the wave's viewing rays
  std::vector<uint32_t> ray_path;            // which path each viewing ray belongs to
  std::vector<std::optional<Hit>> hits;
  std::vector<Ray> shadow_rays;
  std::vector<vec3> shadow_values;  // radiance each adds if unblocked
  std::vector<uint32_t> shadow_path;
  std::vector<int> shadow_light;       // the light each shadow ray goes to
  std::vector<uint32_t> sorted_index;  // the shadow rays grouped by light: indices into shadow_*
  std::vector<uint32_t> light_start;   // counting sort offsets, one per light + 1
  std::unique_ptr<bool[]> blocked;     // not std::vector<bool>: occluded_many writes a bool array
  std::vector<int> lens_order, point_order, select_order, gather_order;
  std::vector<int> specular_order[PathSamples::kStratifiedBounces];

  void resize(size_t paths, size_t pixels) {
    if (samples.size() < paths) {
      samples.resize(paths);
      rngs.resize(paths);
      rays.resize(paths);
      ray_path.resize(paths);
      hits.resize(paths);
      shadow_rays.resize(paths);
      shadow_values.resize(paths);
      shadow_path.resize(paths);
      shadow_light.resize(paths);
      sorted_index.resize(paths);
      blocked.reset(new bool[paths]);
    }
    if (choices.size() < pixels) choices.resize(pixels);
  }
};

}  // namespace

void HqRenderer::render_tile(const ThinLensCamera& camera, int tile, int pass,
                             std::vector<vec3>& out, HqRayCounts& counts,
                             const std::function<bool(uint64_t paths)>& wave_done) const {
  const int n = params_.samples_per_side;
  const int count = n * n;
  const int tiles_x = (params_.width + params_.tile_size - 1) / params_.tile_size;
  const int x0 = (tile % tiles_x) * params_.tile_size;
  const int y0 = (tile / tiles_x) * params_.tile_size;
  const int x1 = std::min(x0 + params_.tile_size, params_.width);
  const int y1 = std::min(y0 + params_.tile_size, params_.height);
  const int tile_width = x1 - x0;
  const int tile_pixels = tile_width * (y1 - y0);

  const size_t strata = size_t(count);
  const size_t max_paths = size_t(params_.max_wave_paths);
  const int wave_pixels_max = int(std::clamp<size_t>(max_paths / strata, 1, kWavePixels));
  const size_t chunk_max = std::min(strata, max_paths);  // < strata: one pixel per wave
  thread_local WaveBuffers buffers;
  WaveBuffers& b = buffers;
  b.resize(size_t(wave_pixels_max) * chunk_max, size_t(wave_pixels_max));
  b.lens_order.resize(strata);
  b.point_order.resize(strata);
  b.select_order.resize(strata);
  b.gather_order.resize(strata);
  for (auto& order : b.specular_order) order.resize(strata);
  thread_local std::vector<Path> paths;
  paths.resize(std::max(paths.size(), size_t(wave_pixels_max) * chunk_max));
  thread_local std::vector<Rng> pixel_rngs;
  pixel_rngs.resize(size_t(wave_pixels_max));

  for (int first = 0; first < tile_pixels; first += wave_pixels_max) {
    const int wave_pixels = std::min(wave_pixels_max, tile_pixels - first);
    for (size_t s0 = 0; s0 < strata; s0 += chunk_max) {
      const size_t chunk = std::min(chunk_max, strata - s0);
      // The primaries: per pixel, its strata and sample numbers from Rng(hash_seed(seed, pass,
      // pixel)) in sample order; each path's specular bounces draw from a stream of its own
      // (seeded from the pixel's seed and the sample), so no path's numbers depend on another's.
      for (int i = 0; i < wave_pixels; ++i) {
        const int x = x0 + (first + i) % tile_width;
        const int y = y0 + (first + i) / tile_width;
        const uint64_t pixel = uint64_t(y) * uint64_t(params_.width) + uint64_t(x);
        const uint64_t pixel_seed = hash_seed(params_.seed, uint64_t(pass), pixel);
        // The pixel's sequence shifts (sobol_points.h), the same in every pass, so its passes'
        // film, lens, light and gather points stratify together: 16 passes of 4 x 4 samples
        // are 16 x 16 strata in each, not sixteen 4 x 4 grids drawn again.
        const uint64_t pixel_key = hash_seed(params_.seed, pixel, 0x50b01);
        const uint64_t film_shift = mix64(pixel_key ^ 1), lens_shift = mix64(pixel_key ^ 2),
                       point_shift = mix64(pixel_key ^ 3), gather_shift = mix64(pixel_key ^ 4);
        uint64_t specular_shift[PathSamples::kStratifiedBounces];
        for (int k = 0; k < PathSamples::kStratifiedBounces; ++k)
          specular_shift[k] = mix64(pixel_key ^ uint64_t(5 + k));
        const uint32_t pass_first = uint32_t(uint64_t(pass) * strata);
        Rng& rng = pixel_rngs[size_t(i)];
        if (s0 == 0) {
          rng = Rng(pixel_seed);
          // Uncorrelated jittering (Cook 1986): the lens, light-point, light-choice and gather
          // strata are dealt to the pixel's film strata through independent permutations.
          std::iota(b.lens_order.begin(), b.lens_order.end(), 0);
          std::iota(b.point_order.begin(), b.point_order.end(), 0);
          std::iota(b.select_order.begin(), b.select_order.end(), 0);
          shuffle(b.lens_order, rng);
          shuffle(b.point_order, rng);
          shuffle(b.select_order, rng);
          if (params_.final_gather > 0) {  // drawn only then: fewer numbers without it
            std::iota(b.gather_order.begin(), b.gather_order.end(), 0);
            shuffle(b.gather_order, rng);
          }
          b.choices[size_t(i)].valid = false;  // a pixel's choice never leaks into the next
          // From a stream of their own, so the pixel's other numbers keep their bits.
          Rng specular_rng(hash_seed(pixel_seed, 0x5bec));
          for (auto& order : b.specular_order) {
            std::iota(order.begin(), order.end(), 0);
            shuffle(order, specular_rng);
          }
        }
        for (int s = int(s0); s < int(s0 + chunk); ++s) {
          const size_t p = size_t(i) * chunk + (size_t(s) - s0);
          const vec2 film = vec2(float(x), float(y)) +
                            shifted_sobol_point(pass_first + uint32_t(s), film_shift);
          const vec2 lens = shifted_sobol_point(pass_first + uint32_t(b.lens_order[size_t(s)]),
                                                lens_shift);
          PathSamples& samples = b.samples[p];
          samples.light_point = shifted_sobol_point(
              pass_first + uint32_t(b.point_order[size_t(s)]), point_shift);
          samples.light_select =
              (float(b.select_order[size_t(s)]) + rng.next_float()) / float(count);
          samples.choice = &b.choices[size_t(i)];
          for (int k = 0; k < PathSamples::kStratifiedBounces; ++k)
            samples.specular[k] = shifted_sobol_point(
                pass_first + uint32_t(b.specular_order[k][size_t(s)]), specular_shift[k]);
          samples.stratified_bounces = PathSamples::kStratifiedBounces;
          if (params_.final_gather > 0) {
            // The gather's points: pass k holds the pixel's sequence points k x count x F on,
            // dealt to its samples through their own permutation; one shift for all passes.
            const uint32_t point = pass_first + uint32_t(b.gather_order[size_t(s)]);
            samples.gather_strata.first_index = point * uint32_t(params_.final_gather);
            samples.gather_strata.shift = gather_shift;
            samples.gather_stream = hash_seed(pixel_seed, uint64_t(s) + 1, 0x6a7e);
          }
          // Built in place: copying a just-built temporary stalls on store forwarding.
          std::construct_at(&b.rngs[p], hash_seed(pixel_seed, uint64_t(s) + 1));
          camera.generate(film, lens, b.rays[p]);
          b.ray_path[p] = uint32_t(p);
          paths[p] = Path{};
        }
      }

      // The bounces: one wave of viewing rays, then one wave of the shadow rays they asked for.
      // Coherent flag for both: the primaries of a wave leave one lens through neighbouring
      // pixels, the shadow rays (grouped by light) leave neighbouring points towards one light,
      // and a specular bounce of such rays stays close (as in the illumination pass).
      size_t active = size_t(wave_pixels) * chunk;
      for (int depth = 0; active > 0 && depth <= params_.max_depth; ++depth) {
        accel_->intersect_many(b.rays.data(), active, b.hits.data(), /*coherent=*/true);
        counts.viewing += active;
        size_t continuing = 0, shadows = 0;
        for (size_t k = 0; k < active; ++k) {
          const uint32_t p = b.ray_path[k];
          // The next ray and the shadow ray go straight into their buffers' next free slots
          // (continuing <= k: advance reads ray k before it writes slot `continuing`).
          DeferredEstimate shadow;
          const bool more = advance(b.hits[k], b.rays[k], b.samples[p], b.rngs[p], paths[p],
                                    b.rays[continuing], shadow, b.shadow_rays[shadows], counts);
          if (shadow.shadow_ray) {
            b.shadow_values[shadows] = shadow.value;
            b.shadow_path[shadows] = p;
            b.shadow_light[shadows] = shadow.light;
            ++shadows;
          }
          if (more) {
            b.ray_path[continuing] = p;
            ++continuing;
          }
        }
        // By light, in path order within a light (a counting sort): Embree's packets then hold
        // rays from neighbouring points to one light (bench_hq ShadowWaveOrder: 21 vs 38 ns per
        // ray in path order with 9 lights; the same with one).
        // With one light the sort is the identity: skipped (its count, one counter bumped per
        // ray, is a chain of dependent stores).
        const size_t lights = direct_->light_count();
        const bool sort = lights > 1;
        if (sort) {
          b.light_start.assign(lights + 1, 0);
          for (size_t k = 0; k < shadows; ++k) ++b.light_start[size_t(b.shadow_light[k]) + 1];
          for (size_t j = 0; j < lights; ++j) b.light_start[j + 1] += b.light_start[j];
          for (size_t k = 0; k < shadows; ++k)
            b.sorted_index[b.light_start[size_t(b.shadow_light[k])]++] = uint32_t(k);
          accel_->occluded_many(b.shadow_rays.data(), b.sorted_index.data(), shadows,
                                b.blocked.get(), /*coherent=*/true);
        } else {
          accel_->occluded_many(b.shadow_rays.data(), shadows, b.blocked.get(), /*coherent=*/true);
        }
        for (size_t k = 0; k < shadows; ++k) {
          // One shadow ray per path per wave, so the order of these adds does not matter.
          const uint32_t i = sort ? b.sorted_index[k] : uint32_t(k);
          if (!b.blocked[k]) paths[b.shadow_path[i]].radiance += b.shadow_values[i];
        }
        counts.shadow += shadows;
        active = continuing;
      }

      // Each pixel sums its samples in sample order, chunk after chunk.
      for (int i = 0; i < wave_pixels; ++i) {
        const int x = x0 + (first + i) % tile_width;
        const int y = y0 + (first + i) / tile_width;
        vec3& sum = out[size_t(y) * size_t(params_.width) + size_t(x)];
        if (s0 == 0) sum = vec3(0.0f);
        for (size_t s = 0; s < chunk; ++s) sum += paths[size_t(i) * chunk + s].radiance;
      }
      counts.samples += uint64_t(wave_pixels) * uint64_t(chunk);
      if (!wave_done(uint64_t(wave_pixels) * uint64_t(chunk))) return;
    }
  }
}

}  // namespace lb
