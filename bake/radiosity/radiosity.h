#pragma once
// Pass 2: soft indirect light by ray-traced progressive shooting (Shirley 1990, section 3.2,
// second listing). Each light shoots first; the power it deposits on diffuse patches is kept
// as unsent but not counted as received (the paper's "set Phi_i to zero"), so only light that
// met two or more diffuse surfaces remains. Then the patch with the most unsent power shoots,
// again and again. Rays that hit mirrors, glass or glossy metal carry on with k = k * weight
// (bsdf.h) and deposit on the first diffuse patch they reach.
//
// Every light kind shoots first, through LightSources (bake/light_sources.h): area lights from
// their triangles, lamps and the sky from LightSources::emit (a point lamp over the sphere, a
// spot over its outer cone with its falloff in each ray's power, directional lamps and the
// sky as parallel rays from a disk covering the scene; a lamp's range window fades each ray
// at its first hit, the faded power booked as absorbed). Area lights' and lamps' first
// deposits are direct light (the viewer's and HQ's): never counted. The sky's are counted
// where the first hit is diffuse: the sky is not evaluated at view time, so the stored soft
// light includes its first bounce (a constant sky L over an open floor stores L); sky light
// through mirrors or glass first is a caustic (pass 1's maps) and not counted.
//
// Stored result (bake_result.h convention): per vertex of the refined mesh, the incident
// irradiance of that soft light over pi, before reflectance: Phi_incident / (pi * A) per patch,
// then averaged onto vertices (patches.h). Incident power is tracked directly, so channels
// with zero reflectance are fine.
//
// Emitters that are diffuse: they shoot their emission as lights and, with `emitters_reflect`
// (default), are also ordinary patches that receive and re-shoot light (physically right; a
// closed sphere with an emitting cap then matches rho P / ((1 - rho) pi A) exactly). With
// emitters_reflect = false they are lights only: light reaching them is absorbed.
// Back faces of diffuse surfaces are black: a ray that reaches one is absorbed, unless the
// material is two-sided (Material::two_sided_reflection): the back's reflected power is shot
// from the back; only the front's light is stored.
//
// Ray allocation: a shot of power Phi gets n_r = max(min_rays_per_shot, Phi * rays_per_watt)
// rays (rounded up to a square so the m x m direction strata are complete), with
// rays_per_watt = ray_budget * (1 - rho) / Phi_emitted, rho the area-weighted mean patch
// reflectance (clamped to 0.95): the geometric series Phi_emitted / (1 - rho) estimates all
// power ever shot, so the whole solve spends about `ray_budget` rays. Hard caps: max_shots
// and max_rays.
//
// Determinism: the rays of a shot are cut into fixed blocks of 128 (each traced as one wave
// through Embree's stream API), ray k of block b of shot s draws from a generator keyed by
// (seed, s, b) and k, the pairing of origin and direction strata is a permutation drawn from
// (seed, s) alone, and per-block deposits are merged in block order: the same bits whatever
// the thread count.

#include <cstdint>
#include <functional>
#include <vector>

#include "bake/accel.h"
#include "bake/bake_result.h"
#include "bake/progress.h"
#include "bake/radiosity/patches.h"

namespace lb {

struct RadiosityParams {
  // Target patch edge, metres; 0 = automatic (patches.h: about 16 x 16 patches on the
  // largest wall). Meshes' own bake settings take precedence. Smaller patches give
  // finer soft shadows but need proportionally more rays for the same noise.
  float patch_size = 0.0f;
  // Total rays for the whole solve (typical 1e6..1e8), spread over shots in proportion to
  // the power each shot carries (see above). Noise falls as 1/sqrt(budget / patch count).
  uint64_t ray_budget = 4'000'000;
  // Fewest rays in any shot (>= 1), so the tail of low-power shots still samples directions.
  // With very many patches (1e5) shots * min_rays can exceed the budget: raise the budget.
  uint64_t min_rays_per_shot = 16;
  // Stop when the unsent power falls below this fraction of the emitted power (per channel;
  // of lamps and the sky only the part their rays brought into the scene counts: a disk
  // around the scene sends most of its power past it).
  double convergence = 1e-3;
  // Hard caps on work, so albedo near 1 cannot run forever. 0 = automatic, scaled to the patch
  // count so that a fine bake converges: max_shots = max(100000, 128 * patches) (a solve
  // measured 7 shots per patch at rho ~0.7), max_rays = 4 * budget + 2 * min_rays_per_shot *
  // max_shots (the tail of minimum-size shots cannot exhaust it).
  uint64_t max_shots = 0;
  uint64_t max_rays = 0;
  // Specular bounces a ray may take before its power is dropped (counted as absorbed).
  int max_specular_depth = 16;
  // Diffuse emitters also receive and reflect light (see above).
  bool emitters_reflect = true;
  // Cut patches along contacts with other geometry and never shoot from covered triangles
  // (contact_cuts.h). Off only to measure what it fixes.
  bool contact_cuts = true;
  uint64_t seed = 1;
};

// Optional hooks into a running solve (the viewer's live refinement), apart from the params
// because they are not settings of the result.
struct RadiosityCallbacks {
  // Called on the solving thread between shots with the solution so far: vertex radiance
  // from the power received up to now, converted exactly as at the end, and the stats of
  // that moment (residual recomputed, `converged` false). It only reads the solver's state,
  // so the final result has the same bits with or without it; unset, it costs nothing.
  // Received power only grows, so successive partials grow towards the final result.
  std::function<void(const VertexRadiosity&)> on_partial;
  // At most this often: both must have passed since the previous call (or the first shot).
  double min_interval_seconds = 0.25;
  uint64_t min_interval_shots = 1;
  // When set, every ray the solve casts is appended here, in the deterministic order of the
  // shots and their blocks (the benchmarks' yardsticks trace the very same rays).
  std::vector<Ray>* cast_log = nullptr;
};

// Throws std::invalid_argument naming the setting when `params` would ask for more than the
// caps in bake/work_limits.h or this machine's memory (patch count estimated from the scene),
// or are out of range. solve_radiosity calls it first; call it earlier to fail before pass 1.
void check_radiosity_params(const Scene& scene, const RadiosityParams& params);

VertexRadiosity solve_radiosity(const Scene& scene, const Accel& accel,
                                const RadiosityParams& params, const Progress& progress = {},
                                const RadiosityCallbacks& callbacks = {});

// Mean over vertices and channels of |a - reference| / reference, where reference > 0: how
// far a solution is from a converged one (tests and the error-against-time benchmarks).
// Both must come from the same scene and patch size.
double mean_relative_error(const VertexRadiosity& a, const VertexRadiosity& reference);

// The scene the pass traces: every mesh with patches replaced by its refined mesh.
Scene refined_scene(const Scene& scene, const Patches& patches);

}  // namespace lb
