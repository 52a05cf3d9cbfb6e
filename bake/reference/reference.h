#pragma once
// The reference renderer: an unbiased estimate of the radiance the camera sees, built from
// the core only (scene, accelerator, lights, BSDFs, thin-lens camera, bump maps). It shares
// nothing with the three passes (no illumination maps, no radiosity, no patches, no HQ baked
// terms), so a wrong decomposition shows as a difference against it.
//
// ---- Path space and who counts what ------------------------------------------------------
// Vertices: E (the lens), L (a point on an emitter's front face), D (a diffuse surface: the
// Lambertian material, two-sided: it reflects on the side the light arrives from), S (mirror,
// glass and glossy metal: the "specular" materials of bsdf.h, as the bake's pass 1 treats them).
// An emitter is also a reflector of its material's kind (a diffuse light reflects with its
// reflectance). Every path from a light to the eye is counted by exactly one estimator:
//  - light tracing (light_tracer.h) counts exactly the paths  L S+ D E : particles leave the
//    lights, pass through one or more specular vertices, and at the first diffuse vertex are
//    connected to the lens (caustics seen directly on diffuse surfaces);
//  - the path tracer (path_tracer.h) counts every other path. Walking from the eye, it finds
//    emitted light in two ways: next-event estimation at diffuse vertices (D L) and by hitting
//    an emitter with a scattered ray. The two are combined by the power heuristic when the ray
//    left a diffuse vertex; after a specular vertex only the hit can find the light (mirrors
//    and glass are delta; glossy is treated as the bake treats it, sampled, never connected),
//    so it counts with weight 1 - EXCEPT when the eye path so far is  E D S+  (its first
//    vertex diffuse, every later one specular): that path is  L S+ D E, the light tracer's.
// Lamps and the sky (bake/light_sources.h): L is also a point or spot lamp's point, a
// directional lamp or the sky. No scattered ray can hit a delta lamp (point, spot,
// directional), so the path tracer finds them by next-event estimation alone (weight 1, no
// MIS) and light tracing, which starts from lamps too, is the only way to their caustics
// L S+ D E, and also counts L S+ D (D|S)* D E from them (it goes on past the first diffuse
// vertex, connecting at each). The sky is found both ways by the path tracer (next-event estimation
// drawing from SkyLight, and rays that leave the scene, combined by the power heuristic after a
// diffuse vertex, weight 1 otherwise, E D S+ sky included): light tracing does not start from
// the sky. Not counted by either, so missing: a delta lamp's light whose first vertex is
// specular and whose last vertex before the eye is specular too (L S+ D ... S+ E: a lamp's
// caustic seen in a mirror, which no unbiased method samples with a pinhole).
// Glossy vertices get no next-event estimation: highlights of small lights are found by the
// sampled reflection alone (unbiased, noisier); this matches the bake's partition, in which
// glossy is specular.
//
// `terms = direct` keeps only the paths  E S* L  and  E S* D L  (light that reached the first
// diffuse surface straight from a light, and lights seen directly or through specular
// surfaces): what HQ mode's direct term estimates (HqParams: illumination_map = radiosity =
// false). No light tracing then.
//
// ---- Estimators ---------------------------------------------------------------------------
// One pass = one eye path per pixel (uniform point in the pixel, uniform point on the lens)
// plus light_paths_per_pixel * width * height light paths, whose splats are divided by that
// count. Each pass is an independent unbiased estimate of the image; passes accumulate
// (film.h, with the noise estimate from even/odd halves). Russian roulette below a throughput
// threshold (as HQ mode does); max_depth is only a guard against endless total internal
// reflection (see its comment).
// Radiance through glass carries no (n1/n2)^2 factor, as bsdf.h's weights do not: exact for
// a camera and lights outside closed glass objects, which enter and leave it equally.
//
// ---- Determinism --------------------------------------------------------------------------
// Pixel p of pass k draws from Rng(hash_seed(seed, k, 2^41 + p)); light block b of pass k
// from Rng(hash_seed(seed, k, 2^40 + b)) (streams apart from HQ mode's, see reference.cpp); tiles
// and blocks are fixed, block splats are added in block order. Same seed and pass count = same
// bits, whatever the thread count.
// Shards (issue 16): shard i of n renders the passes k with k mod n = i, each pass exactly as
// the whole render does it; the film's fixed-point sums (film.h) add in any order, so the
// shards' films summed have the bits of the whole render's.

#include <cstdint>
#include <memory>
#include <vector>

#include "bake/accel.h"
#include "bake/progress.h"
#include "bake/reference/film.h"
#include "bake/scene.h"

namespace lb::reference {

enum class Terms { all, direct };

// A rectangle of pixels, (x, y) its top-left corner (row 0 at the top).
struct PixelWindow {
  int x = 0;
  int y = 0;
  int width = 0;  // 0 (with height 0): no window, the whole image
  int height = 0;
  bool empty() const { return width == 0 && height == 0; }
};

struct ReferenceParams {
  int width = 640;   // pixels
  int height = 480;  // pixels
  int spp = 64;      // passes = samples (eye paths) per pixel; the render stops after this many
  // Wall-clock seconds after which no new pass starts (the current one finishes); 0 = no limit.
  // The render always does at least one pass. A time limit makes the pass count, and so the
  // bits, depend on the machine; the spp count alone does not.
  double time_limit_seconds = 0.0;
  uint64_t seed = 1;
  // Light paths per pass = this * width * height, rounded up (caustic noise against cost:
  // most light paths end at their first, diffuse, hit for one ray). 0 leaves the caustics
  // seen directly out of the image (a debug view of everything else).
  double light_paths_per_pixel = 1.0;
  // Cross-check of the partition: false lets the path tracer count L S+ D E as well (by its
  // scattered rays hitting the light, unbiased but slow for small lights) and traces no light
  // paths. Both settings estimate the same image, except for delta lamps' caustics, which only
  // light tracing finds (false leaves them out).
  bool light_tracing = true;
  // Russian roulette: a path whose throughput (max channel; for light paths relative to what
  // left the light) falls below this survives with probability throughput / threshold and
  // then carries the threshold. Higher = shorter paths, more noise; 0.05 keeps a white
  // furnace's noise well below 1% at a few hundred spp.
  float roulette_threshold = 0.05f;
  // Scattering vertices before a path is dropped: a guard, not a depth cut in practice. With
  // roulette a path survives past vertex n with probability below the product of its albedos;
  // only a path trapped at weight 1 (total internal reflection) can get here (measured in
  // docs/reference.md).
  int max_depth = 1000;
  int tile_size = 16;           // pixels per tile edge; fixed, so work splits the same way
  int light_block_size = 4096;  // light paths per block (one Rng stream, one splat list)
  Terms terms = Terms::all;
  // Render only the passes k < spp with k mod shard_count = shard (`lightbake reference
  // --shard`); not with a time limit, which would make each shard's pass count a matter of
  // its machine's clock.
  int shard = 0;
  int shard_count = 1;
  // Render only these pixels of the width x height image (`lightbake reference --window`):
  // each window pixel's eye paths draw from the stream of its index in the whole image, and
  // every light path of the whole image is traced (only splats that land in the window are
  // kept, their connection rays only then cast), so the window's pixels have the bits of the
  // same pixels of the whole render. The film is the window's size. Empty = the whole image.
  PixelWindow window;
};

// The window a render covers: params.window, or the whole image when that is empty.
PixelWindow render_window(const ReferenceParams& params);

// The window's pixels (a film's average) placed in the whole width x height image, 0 elsewhere.
std::vector<vec3> window_in_image(const std::vector<vec3>& window_pixels,
                                  const ReferenceParams& params);

// Passes of `params.spp` that shard `params.shard` renders.
int shard_passes(const ReferenceParams& params);

// Rays by kind (Embree calls), as in the paper's Table 1.
struct ReferenceRays {
  uint64_t camera = 0;      // the eye paths' first rays
  uint64_t bounce = 0;      // eye paths' later rays (diffuse and specular scattering)
  uint64_t shadow = 0;      // next-event estimation visibility tests
  uint64_t light = 0;       // light paths' rays (emission and specular scattering)
  uint64_t connection = 0;  // light-path vertex to lens visibility tests
  uint64_t eye_paths = 0;
  uint64_t light_paths = 0;
  uint64_t cut_at_max_depth = 0;  // paths dropped by the max_depth guard (its only bias)
  uint64_t total() const { return camera + bounce + shadow + light + connection; }
  ReferenceRays& operator+=(const ReferenceRays& r) {
    camera += r.camera, bounce += r.bounce, shadow += r.shadow, light += r.light;
    connection += r.connection, eye_paths += r.eye_paths, light_paths += r.light_paths;
    cut_at_max_depth += r.cut_at_max_depth;
    return *this;
  }
};

struct ReferenceStats {
  ReferenceRays rays;
  double wall_seconds = 0.0;
  double cpu_seconds = 0.0;  // user + system of the whole process over the passes
  std::vector<double> pass_seconds;
};

class ReferenceRenderer {
 public:
  // `scene` and `accel` must outlive the renderer. Throws std::invalid_argument on bad params.
  ReferenceRenderer(const Scene& scene, const Accel& accel, const Camera& camera,
                    const ReferenceParams& params);
  ~ReferenceRenderer();

  const ReferenceParams& params() const { return params_; }

  // Pass number `pass` into `film` (resized and cleared if its size differs). A cancelled pass
  // throws lb::Cancelled and leaves `film` as it was.
  void render_pass(Film& film, uint64_t pass, ReferenceStats& stats,
                   const Progress& progress = {}) const;
  // The shard's passes (all of them unsharded) until they are done or the time limit passes;
  // returns the film.
  Film render(ReferenceStats& stats, const Progress& progress = {}) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  ReferenceParams params_;
};

// Throws std::invalid_argument naming the first bad field.
void check_reference_params(const ReferenceParams& params);

}  // namespace lb::reference
