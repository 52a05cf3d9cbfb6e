#pragma once
// Final gather of the soft (radiosity) term: one diffuse bounce gathered from the bake instead
// of interpolating the vertex radiosity at the shading point (issue 11).
//
// What it estimates, in the stored convention of bake/bake_result.h: the soft term at x is the
// irradiance E/pi from light that met >= 2 diffuse surfaces counting x, i.e. light that left
// some diffuse surface y (possibly through mirrors/glass/glossy metal on the way) towards x:
//     soft(x) = 1/pi \int_H L_y(w) cos(w) dw,
//     L_y = R(y) * (direct(y) + illumination_map(y) + soft(y))      (y's reflected radiance).
// With cosine-weighted directions (pdf cos / pi) the estimate is the mean of L_y over the rays.
//
// Which solution quantities at y, and why: direct(y) is HQ's one-shadow-ray estimator
// (direct_light.h) at the hit, unbiased and exact in the shadows' shape; the map and soft(y)
// are the bake's, looked up as HQ does (baked_terms.h). So the first indirect bounce (light ->
// diffuse -> x), most of the soft light and all of its sharp features, comes without the
// patches' bias; only the >= 2-bounce-before-x part (a factor ~rho smaller and smoother) keeps
// the interpolation's. The alternative, each patch's total received power (direct included),
// is piecewise constant per patch: it would keep the patch-size bias of shadows and contacts on
// y that this gather is meant to remove, and the bake does not store it. The cost is one
// shadow ray per gather ray.
//
// Hits, as the radiosity pass counts them: misses give 0, except a gather ray that leaves x
// straight to the sky, which returns the sky's radiance (the sky seen from a diffuse surface
// is soft light; the sky through specular surfaces is caustic light, the maps'); the back face of a
// diffuse surface is black (the pass absorbs rays there, so its soft term has no light through back
// faces), except on a two-sided surface (Material::two_sided_reflection, glTF doubleSided), whose
// back reflects R (its direct light + what one more cosine-distributed ray from that side
// gathers): the bake stores the front's light only; an emitter's own emission is never counted
// (at x it is direct or caustic light), but a diffuse emitter reflects like any diffuse surface
// (RadiosityParams::emitters_reflect);
// mirrors, glass and glossy metal are followed through lb::scatter_specular (D S+ D paths are
// soft light, as in the pass) with Russian roulette below a throughput of 0.01, up to
// `max_specular_depth` bounces.
//
// Deterministic: every number a point's rays draw comes from Rng(stream), so the result
// depends on (point, stream, samples, cell) only, not on threads or call order. Thread-safe:
// call it from any number of threads on one context. Use, e.g. for lightmap texels:
//     const Accel accel(baked.scene);
//     const DirectLight direct(baked.scene, accel);
//     const GatherContext context{baked, accel, direct};
//     soft[texel] = gather_soft_light(context, receiver, hash_seed(seed, texel), 256);

#include <cstdint>
#include <optional>

#include "bake/accel.h"
#include "bake/bake_result.h"
#include "bake/transport/direct_light.h"
#include "bake/sampling.h"
#include "bake/surface.h"

namespace lb {

// Light groups (bake/light_groups.h): each group's terms at the gather's hits, so that one
// gather ray gives every group's soft light (gather_soft_light's `group_means`): at a diffuse
// hit, the direct estimate goes to its light's group, each group's map and vertex radiosity to
// that group, the sky seen straight to the sky's group. For a baked scene without a soft-light
// texel map (the gather then reads vertex radiosity, as soft_texels.h's gather does).
struct GatherGroups {
  size_t groups = 0;
  // The groups' illumination maps, and per scene mesh their vertex radiance, each texel's or
  // vertex's groups side by side (add_group_terms, baked_terms.h).
  std::vector<uint32_t> map_start;
  std::vector<vec3> map_values;
  std::vector<std::vector<vec3>> vertex_radiance;
  std::vector<int> light_group;  // per DirectLight light (area lights, then lamps)
  int sky_group = -1;
  size_t count() const { return groups; }
};

// What a gather reads: the baked scene, an accelerator over baked.scene and the direct-light
// estimator over the same. All must outlive the context.
struct GatherContext {
  const BakedScene& baked;
  const Accel& accel;
  const DirectLight& direct;
  int max_specular_depth = 16;  // specular bounces a gather ray may take
  const GatherGroups* groups = nullptr;  // light groups' terms too (gather_soft_light)
  // Short rays: a hit y nearer than `regather_distance` (metres; 0 = never) to the point the
  // ray left takes its soft term from `regather_rays` gather rays of its own, one bounce more,
  // instead of the vertex radiosity. Near a contact or crease the nearby surface fills much of
  // x's hemisphere, and its vertex radiosity there is its patch's mean, brighter than the
  // crease it meets; the deeper gather's first bounce has no such bias. About a patch edge:
  // beyond it the patches resolve what a hit sees. Not with light groups (their maps are
  // read as they are).
  float regather_distance = 0.0f;
  int regather_rays = 0;
};

// Rays a gather cast, by kind.
struct GatherCounts {
  uint64_t rays = 0;    // intersect() calls (gather rays and their specular bounces)
  uint64_t shadow = 0;  // occluded() calls (direct light at the hits)
};

// A sub-square of the unit square the directions are drawn in (the caller's stratum): HQ gives
// each of a pixel's samples its own cell, so a pixel's gather rays stratify the hemisphere.
struct SampleCell {
  vec2 origin{0.0f};
  vec2 size{1.0f};
};

// Or consecutive points of Sobol's sequence (sobol_points.h): ray k of a call takes point
// first_index + k, digitally shifted by `shift`: its direction from dimensions 0 and 1, the
// light point of its hit's shadow ray from 2 and 3. HQ numbers a pixel's gather rays across
// its passes (shift per pixel), so all its passes' rays stratify the hemisphere together:
// pass k's 16 rays a 4 x 4 grid, 16 passes a 16 x 16 one.
struct SobolStrata {
  uint32_t first_index = 0;
  uint64_t shift = 0;
};

// The receiver at a diffuse surface point seen by a ray travelling along `arrival`: normals
// turned to that side, the shading normal bump-mapped (the geometric one where they disagree).
// HQ's viewing paths and the gather's hits use it; a caller with a surface point (a lightmap
// texel, say) passes the direction it looks at the surface from, e.g. -geometric_normal for
// the front side.
ReceiverPoint receiver_at(const Scene& scene, const SurfacePoint& sp, vec3 arrival);

// The soft term at receiver x (normals on the side light arrives from, shading normal for the
// cosine), in E/pi W/(sr m^2) before x's reflectance. `samples` >= 1 rays on a jittered grid
// inside `cell` (the rays beyond the largest square uniform over it), mapped to the hemisphere
// about x's shading normal by the concentric map (directions below the geometric surface give
// 0). Unbiased given the bake's map and soft terms.
// With context.groups and `group_means` (context.groups->count() entries), each group's part
// of the estimate is written there too (the same rays; they sum to the return value).
vec3 gather_soft_light(const GatherContext& context, const ReceiverPoint& x, uint64_t stream,
                       int samples, const SampleCell& cell = {}, GatherCounts* counts = nullptr,
                       vec3* group_means = nullptr);
// The same estimate with its directions from the sequence (unbiased over the shift).
vec3 gather_soft_light(const GatherContext& context, const ReceiverPoint& x, uint64_t stream,
                       int samples, const SobolStrata& strata, GatherCounts* counts = nullptr);

// Outgoing radiance towards -direction of what `ray` hits, as defined above (reflected light
// only, no emission), following specular surfaces; `rng` draws the specular bounces and the
// direct-light samples (the light point is `light_point` instead when given). One gather
// ray's value.
// `group_radiance` (context.groups): each group's part added there.
vec3 gathered_radiance(const GatherContext& context, Ray ray, Rng& rng, GatherCounts& counts,
                       const vec2* light_point = nullptr, vec3* group_radiance = nullptr);

// The pieces of a gather, for callers that trace many points' rays in waves (gather_waves.h);
// gathered_radiance and gather_soft_light are made of these.

// The side m of the jittered m x m grid gather_soft_light puts `samples` rays on (m^2 <=
// samples), and ray k's point in `cell`: jittered in its stratum for k < m^2, else uniform over
// the cell (two numbers from rng either way).
int gather_grid_side(int samples);
vec2 gather_cell_point(int k, int m, const SampleCell& cell, Rng& rng);
// The gather ray from x along the cosine-weighted direction of `unit` about `frame` (x's
// shading normal); false when that direction lies below x's geometric surface (the ray then
// counts 0, nothing traced).
bool gather_ray(const ReceiverPoint& x, const Frame& frame, vec2 unit, Ray& ray);

// Where a gather ray's walk stopped: done (`radiance` is its value), or at the front of a
// diffuse surface, its direct light sampled and the shadow ray still to trace.
struct GatherStop {
  vec3 radiance{0.0f};  // gathered on the way (the backs of two-sided surfaces, the sky)
  bool at_diffuse = false;
  SurfacePoint sp;             // at_diffuse: the hit
  vec3 throughput{1.0f};       // at_diffuse: the path's weight there
  DeferredEstimate direct;     // at_diffuse: the direct light, if shadow_ray is unblocked
  Ray shadow_ray;
  ReceiverPoint y;             // at_diffuse: the hit as a receiver
  uint64_t regather = 0;       // at_diffuse: the stream of its own soft gather; 0 = none
};
// gathered_radiance up to its last shadow ray, the ray's first intersection `hit` given
// (Accel::intersect's or intersect_many's); the later bounces are traced here, one by one.
GatherStop walk_gather_ray(const GatherContext& context, Ray ray, std::optional<Hit> hit,
                           Rng& rng, GatherCounts& counts, const vec2* light_point,
                           vec3* group_radiance);
// The ray's value once its shadow ray is traced (`blocked`: what context.direct.accel(), which
// may differ from context.accel, answers; ignored without one); group parts added to
// `group_radiance` as gathered_radiance does; a short ray's own gather counted in `counts`.
vec3 finish_gather_ray(const GatherContext& context, const GatherStop& stop, bool blocked,
                       vec3* group_radiance, GatherCounts& counts);

}  // namespace lb
