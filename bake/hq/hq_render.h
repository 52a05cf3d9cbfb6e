#pragma once
// High-quality mode: a distributed ray tracer (Cook 1986) over the baked scene, after
// Shirley 1990 section 3.3. Per pixel N x N stratified viewing rays through a thin lens; at a
// diffuse hit the outgoing radiance is
//     L = R * (direct + illumination_map + vertex_radiosity)
// (R: reflectance with its texture; direct: ONE shadow ray, see direct_light.h, with the
// bump-mapped normal; the two baked terms as stored, see baked_terms.h). Mirrors, glass and
// glossy metal continue the path through lb::scatter_specular (one stochastic branch per
// bounce, Fresnel-chosen for glass, so every viewing ray ends in at most one diffuse hit and
// at most one shadow ray); emitters add their radiance on their front side.
//
// Deterministic: pixel p of pass k draws from Rng(hash_seed(seed, k, p)) and streams seeded from
// it only, tiles are fixed, so the image has the same bits whatever the thread count.
// A tile's paths advance in waves (tile_waves.cpp): each bounce's viewing rays, then its shadow
// rays, go to Embree together through the stream API.

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "bake/accel.h"
#include "bake/bake_result.h"
#include "bake/transport/direct_light.h"
#include "bake/transport/final_gather.h"
#include "bake/progress.h"
#include "bake/sampling.h"

namespace lb {

class ThinLensCamera;

struct HqParams {
  int width = 640;  // pixels
  int height = 480;
  int samples_per_side = 4;         // N: N x N stratified viewing rays per pixel per pass (16)
  int max_depth = 16;               // specular bounces before a path is dropped
  float throughput_cutoff = 0.01f;  // below this (max channel) Russian roulette decides
  // Reuse the light-choice distribution (Eq. 2 over all lights) over the samples of a pixel
  // that hit the same surface: unbiased either way (see DirectLight::Choice), and the per-light
  // cost is paid per pixel instead of per viewing ray. false = the paper's per-hit sweep.
  bool reuse_light_choice = true;
  int tile_size = 16;  // pixels per tile edge; fixed, so work splits the same way
  // Sharding over machines (`render --shard i/n`, `lightbake merge`): this run renders only the
  // tiles t with t % shard_count == shard, the others stay 0. Pixels depend on nothing but
  // their own samples, so the merged shards have the bits of the whole render.
  int shard = 0;
  int shard_count = 1;
  // Most viewing paths a thread holds at once (~150 bytes each): a wave takes fewer pixels at
  // high sample counts, and a pixel with more samples is traced in chunks of this many. Bounds
  // memory whatever the spp. The image does not depend on it in scenes without specular
  // surfaces; with them a pixel's light-choice reuse may pick another anchor (still unbiased).
  int max_wave_paths = 4096;
  uint64_t seed = 1;
  // Debug switches, one per term of the paper's sum (all on for a real render).
  bool direct = true;
  bool illumination_map = true;
  bool radiosity = true;
  // The map's L1 band, where the bake has one (BakedScene::directional), decoded at the bumped
  // normal; off: the map as it is. Read by whoever makes the BakedScene (render, the viewer).
  bool directional = true;
  // Final gather (final_gather.h): gather rays per viewing path at its diffuse hit, which then
  // takes the soft term from one bounce gathered from the bake instead of the interpolated
  // vertex radiosity. 0 = interpolate (the paper's way). Each ray costs one intersect and one
  // shadow ray; a pixel's samples of all passes stratify their gather rays over the
  // hemisphere, so 1 is the cheapest useful value and more samples a pixel do the rest. Waves hold
  // max_wave_paths / (1 + final_gather) paths.
  int final_gather = 0;
};

// Rays by kind, as in the paper's Table 1 (the bake's kinds come from its stats).
struct HqRayCounts {
  uint64_t viewing = 0;        // every intersect() of camera paths: primary and specular bounces
  uint64_t shadow = 0;         // every occluded() test
  uint64_t samples = 0;        // viewing paths started (pixels x spp)
  uint64_t gather = 0;         // final gather: intersect() calls (rays and specular bounces)
  uint64_t gather_shadow = 0;  // final gather: occluded() calls (direct light at its hits)
};

struct HqStats {
  HqRayCounts rays;
  std::vector<double> pass_seconds;
};

// The accumulation buffer: the sum of all samples so far, per pixel.
struct Film {
  int width = 0;
  int height = 0;
  std::vector<vec3> sum;
  uint64_t samples_per_pixel = 0;
  int passes = 0;

  Film() = default;
  Film(int w, int h) : width(w), height(h), sum(size_t(w) * size_t(h), vec3(0.0f)) {}
  void clear() {
    std::fill(sum.begin(), sum.end(), vec3(0.0f));
    samples_per_pixel = 0;
    passes = 0;
  }
  std::vector<vec3> average() const;  // radiance per pixel, W/(sr m^2)
};

// The random numbers one viewing path consumes at its first diffuse hit, stratified by the
// caller over the pixel's samples of all passes (sobol_points.h), each kind dealt to the
// samples through its own permutation (uncorrelated jittering).
struct PathSamples {
  float light_select = 0.5f;
  vec2 light_point{0.5f};
  DirectLight::Choice* choice = nullptr;  // the pixel's cached light choice, if reused
  // Final gather: which of the pixel's sequence points this sample's gather rays take (its
  // passes' rays number on, so they stratify the hemisphere together) and the stream their
  // hits draw from.
  SobolStrata gather_strata;
  uint64_t gather_stream = 0;
  // The first specular bounces' numbers (glass's reflect-or-refract choice, a glossy lobe's
  // direction), stratified like the others: a glass ball's pixels then split their samples
  // between its reflection and refraction in Fresnel's proportion instead of by chance. The
  // first `stratified_bounces` entries are set; later bounces draw from the path's stream.
  static constexpr int kStratifiedBounces = 2;
  vec2 specular[kStratifiedBounces] = {};
  int stratified_bounces = 0;
};

// Throws std::invalid_argument naming the setting when `params` are out of range (sizes in
// [1, 16384], samples per pixel up to kMaxSamplesPerPixel) or the film would not fit in this
// machine's memory. The renderer checks them when built; front ends call it before baking.
void check_hq_params(const HqParams& params);

// Which shard renders pixel (x, y) of an image `width` wide in tiles of `tile_size` (round robin
// over the tiles, row by row, so every shard gets a share of every part of the image).
int hq_tile_of_pixel(int x, int y, int width, int tile_size);
inline int hq_shard_of_tile(int tile, int shard_count) {
  return tile % shard_count;
}
constexpr int kMaxShards = 65536;

class HqRenderer {
 public:
  // Builds its own accelerator over baked.scene; `baked` must outlive the renderer.
  HqRenderer(const BakedScene& baked, const HqParams& params);
  ~HqRenderer();

  const Accel& accel() const { return *accel_; }
  const DirectLight& direct_light() const { return *direct_; }
  const HqParams& params() const { return params_; }

  // One more pass of N x N samples per pixel into `film` (sized params.width x params.height;
  // (re)sized and cleared if it is not). The pass index is film.passes, so successive passes
  // draw new strata. A cancelled pass throws lb::Cancelled and leaves `film` untouched.
  void render_pass(const Camera& camera, Film& film, HqStats& stats,
                   const Progress& progress = {}) const;

  // `passes` passes into a fresh film; returns the averaged image (row 0 at the top).
  std::vector<vec3> render(const Camera& camera, int passes, HqStats& stats,
                           const Progress& progress = {}) const;

  // Radiance along one viewing ray (for tests and a --pixel debug entry).
  vec3 trace(const Ray& ray, const PathSamples& samples, Rng& rng, HqRayCounts& counts) const;

 private:
  // One viewing path's state between bounces.
  struct Path {
    vec3 throughput{1.0f};
    vec3 radiance{0.0f};  // gathered so far (emission, baked terms, unblocked direct light)
    int specular_bounces = 0;
  };
  // One bounce of a viewing path: shades `hit` of `ray` (nullopt: the ray left the scene),
  // adding emission and the baked terms to path.radiance. A diffuse hit ends the path with its
  // direct light in `shadow` and `shadow_ray` (value already times throughput and reflectance;
  // the caller traces the ray). A specular hit writes `next` (which may alias `ray`) and
  // returns true; false when the path ends. trace() and the tile waves share it.
  bool advance(const std::optional<Hit>& hit, const Ray& ray, const PathSamples& samples, Rng& rng,
               Path& path, Ray& next, DeferredEstimate& shadow, Ray& shadow_ray,
               HqRayCounts& counts) const;
  // A tile's pixels in waves (tile_waves.cpp): all their viewing rays of one bounce go to
  // Embree together, then all shadow rays of that bounce. After each wave it tells
  // `wave_done` how many paths it finished, and returns early, the tile unfinished, when that
  // answers false (cancelled): so progress and Ctrl-C work every few milliseconds whatever
  // the tile's sample count.
  void render_tile(const ThinLensCamera& camera, int tile, int pass, std::vector<vec3>& out,
                   HqRayCounts& counts, const std::function<bool(uint64_t paths)>& wave_done) const;

  const BakedScene& baked_;
  HqParams params_;
  std::unique_ptr<Accel> accel_;
  std::unique_ptr<DirectLight> direct_;
  std::unique_ptr<GatherContext> gather_;
};

}  // namespace lb
