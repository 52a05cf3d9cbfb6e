#pragma once
// The light probes' bake (issue 38): a regular grid over the static scene, each probe the L2
// SH of the incident radiance at its point (the convention of bake/probe_grid.h), from the same
// solution the renderers draw. What a probe holds follows the export's lightmap contents:
//   - always, the light that left some surface, and the sky (what the lightmap holds with
//     `--contents indirect`, the default): `directions` rays over the sphere (a spherical
//     Fibonacci lattice, equal solid angles, turned about z per probe; project_sphere), each
//     taking the outgoing radiance of what it meets as the final gather defines it
//     (bake/transport/final_gather.h: reflectance times the hit's direct light, caustic map and soft
//     light, through mirrors and glass; the sky where the ray leaves straight; an emitter's own
//     emission is not counted), projected with weight 4 pi / directions;
//   - with `direct` (`--contents all`): also the light straight from every area light and lamp,
//     sampled from the probe with shadow rays (`light_samples` stratified points an area
//     light, one ray a lamp), each sample's radiance / pdf projected along its direction.
// Without `direct` a renderer adds the direct light itself, per pixel and shadowed, as for every
// surface. Why that is the default: an L2 band cannot hold a compact light (for light from one
// direction its irradiance 90 degrees away comes out ~9% of the peak instead of 0); with the
// direct light in the probes the Cornell box's ball seen from the front drew 2.33x HQ's mean
// radiance, without it 1.67x (bench/probes.py, before dynamic_light.h's shadowing).
// A blend reads only the probes around its point, so a caller that needs no grid (the viewer's
// moving objects, dynamic_light.h) bakes just those with bake_probe.
// Not carried: light reaching the probe's point through glass or off a mirror straight from a
// light (a caustic in mid-air; on surfaces it is the illumination map's).
//
// Validity: a ray's first hit on the back of a one-sided diffuse surface says the probe looks
// at the inside of a solid; a probe with more than `invalid_back_fraction` of its rays doing so
// is invalid, left out of every blend (its coefficients are still written).
//
// Deterministic: probe p's numbers come from hash_seed(seed, p) only, so the grid has the same
// bits whatever the thread count.

#include <cstdint>
#include <functional>

#include "bake/transport/final_gather.h"
#include "bake/probe_grid.h"
#include "bake/progress.h"

namespace lb {

struct ProbeParams {
  // Metres between neighbouring probes; 0: automatic, the longest side of the static scene's
  // bounding box over 16 (a 2 m Cornell box: 0.125 m), widened by 10% steps until the grid
  // holds at most `max_probes`. Each axis then takes ceil(side / spacing) probes at the centres
  // of equal cells, so no probe lies on the box's faces (a closed room's walls).
  float spacing = 0.0f;
  int max_probes = 4096;  // the cap, in [1, 1048576]
  // Gather rays a probe, >= 1. Noise in the indirect part falls as 1/sqrt(directions); 256 keeps
  // the Cornell box's probes within ~1% of 4096 (bench/probes.py).
  int directions = 256;
  // Hold the direct light too (above); off: the renderer adds it.
  bool direct = false;
  int light_samples = 16;  // with `direct`: shadow rays an area light a probe, >= 1 (lamps: one)
  float invalid_back_fraction = 0.25f;  // in [0, 1]
  uint64_t seed = 1;
};

struct ProbeStats {
  size_t probes = 0;
  size_t invalid = 0;
  uint64_t rays = 0;         // gather rays and their bounces
  uint64_t shadow_rays = 0;  // light samples and the gather hits' direct light
  double seconds = 0.0;
};

// The grid's layout (origin, spacing, counts) for the scene's static meshes, no light yet
// (valid all 1, coefficients 0). Empty for a scene without static geometry.
ProbeGrid probe_layout(const Scene& scene, const ProbeParams& params);

// The projection of a radiance field L(w) (w towards the source) as the gather rays make it:
// `directions` points of the spherical Fibonacci lattice (equal solid angles), turned about
// z by an angle drawn from `shift`, c_lm = (4 pi / directions) sum_k L(w_k) Y_lm(w_k).
// Deterministic.
ShL2 project_sphere(const std::function<vec3(vec3)>& radiance, int directions, uint64_t shift);

// One probe at `position`: its coefficients, and the share of its gather rays that met a back
// face. `stream` seeds its numbers.
struct ProbeSample {
  ShL2 sh{};
  float back_fraction = 0.0f;
  bool valid(const ProbeParams& params) const {
    return !(back_fraction > params.invalid_back_fraction);
  }
};
ProbeSample bake_probe(const GatherContext& context, const LightSources& lights, vec3 position,
                       const ProbeParams& params, uint64_t stream, ProbeStats* stats = nullptr);

// Throws std::invalid_argument naming the setting when `params` are out of range.
void check_probe_params(const ProbeParams& params);

// The numbers of the probe at entry `index` of the grid (bake_probe's `stream`).
uint64_t probe_stream(const ProbeParams& params, size_t index);

// Every probe of probe_layout(context.baked.scene, params), in parallel (check_probe_params
// first).
ProbeGrid bake_probes(const GatherContext& context, const ProbeParams& params,
                      ProbeStats* stats = nullptr, const Progress& progress = {});

}  // namespace lb
