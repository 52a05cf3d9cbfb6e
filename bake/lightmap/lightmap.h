#pragma once
// The complete baked light of every diffuse mesh in one lightmap (the export's, issue 12), in
// the convention of bake_result.h (E/pi, W/(sr m^2), before the reflectance):
//
//   caustic  the illumination map of pass 1 (L S+ D), as baked;
//   soft     the bake's soft-light texel map (soft_texels.h: the radiosity solution per
//            texel, corrected by a final gather) when the bake has one, as the viewer draws
//            it; else the radiosity solution resampled into the texels: the refined radiosity
//            meshes carry the lightmap UVs, so their linearly interpolated vertex radiance is
//            integrated exactly against each node's tent (texel_footprint.h, quadrature
//            rule): energy is kept and a uniform field stays uniform to the last bit of a float;
//   direct   with contents `all` only: the light straight from the area lights and lamps
//            (L D) with their shadows, HQ mode's one-shadow-ray estimator
//            (bake/transport/direct_light.h) at side x side stratified points per cell (4 cells a
//            node), deterministic per cell. Not the sky's: its first bounce is soft light
//            (bake/radiosity/radiosity.h), already in the soft term.
//
// `indirect` (default) = caustic + soft, for engines that draw the direct light themselves
// (Unity's Baked Indirect, Godot's dynamic mode); `all` = + direct, for engines that cannot
// draw area lights with shadows. Texels no surface lies under are dilated from their
// neighbours so filtering and mipmaps never see black.
//
// Seams (issue 36): the two sides of every chart seam, in a mesh or between meshes, are made
// to agree under bilinear filtering by least squares (seam_stitch.h).
//
// Contacts (issue 36): surface hidden inside other geometry (under a block, in a wall's
// footprint; the coverage probes of bake/contact_cuts.h on the refined meshes, which
// are cut along contact lines) takes no part in the direct term's texels, and a texel with no
// visible surface at all holds 0, the light inside opaque geometry (a converged Cycles bake of
// the same atlas puts about 0 there too). Without this a texel straddling a block's edge
// averaged the lit floor with the dark under the block (8-12% too dark at 10 texels/m).

#include <cstdint>
#include <string>
#include <vector>

#include "bake/bake_result.h"
#include "bake/lightmap/denoise_texels.h"
#include "bake/lightmap/seam_stitch.h"
#include "bake/lightmap/texel_footprint.h"
#include "bake/lightmap/texel_projection.h"
#include "bake/progress.h"

namespace lb {

enum class LightmapContents { indirect, all };
const char* to_string(LightmapContents contents);
// "indirect" or "all"; throws std::invalid_argument quoting the text otherwise.
LightmapContents parse_lightmap_contents(const std::string& text);

inline constexpr double kDirectPointsBudget = 2097152.0;  // direct_side 0: points over the atlas
inline constexpr int kProjectFromSide = 8;

struct LightmapParams {
  LightmapContents contents = LightmapContents::indirect;
  // Direct light: side x side stratified points per cell, one shadow ray each; a node's value
  // averages its 4 cells (4 x side^2 rays). Range 1..64; noise falls as 1/side, cost grows as
  // side^2. 0 = automatic: as many as kDirectPointsBudget points over the atlas's cells allow,
  // 4 to 16 (side_for_budget): the bundled scenes at their automatic density take 4 (64 rays a
  // texel), the Cornell box at 10 or 5 texels/m 16.
  int direct_side = 0;
  // Shadow rays from shadow_side x shadow_side of a cell's direct_side x direct_side points (one
  // per stratum, weighted by the points it stands for; a cell's average with
  // adaptive_shadow_rays, below); every point still places the texels' fit (the projection) and
  // the closed form. The ratio estimator's share then has this many rays' noise, which the
  // denoiser removes, while the fit keeps all the points. 0 (or >= direct_side): a ray from
  // every point.
  int shadow_side = 0;
  // With shadow_side: the cells' rays as a budget, shadow_side^2 a cell on average, spent where
  // the shadows are (shadow_plan.h): a pilot of half the side finds the cells whose rays
  // disagree, within a cell or with a neighbour's; those and their neighbours take the rest of
  // the budget, more where the pilot saw less light, and count the pilot's rays too; what they
  // leave goes to the dark verdicts nearest them; the others keep the pilot's verdict, which the
  // ratio estimator makes exact (all lit: the closed form; all blocked: 0). False: every cell
  // shadow_side^2 rays.
  bool adaptive_shadow_rays = true;
  // Points on surface hidden inside other geometry take no part in the direct term, and texels
  // with no visible surface hold 0 (the header). Off only to measure what it fixes.
  bool skip_hidden_surface = true;
  // Seams stitched by least squares (seam_stitch.h) after the sum, before the gutters are
  // filled; seam_weight there. Off only to measure what it fixes.
  bool stitch_seams = true;
  // The direct term's texels are the least-squares fit of its points under bilinear filtering
  // (texel_projection.h) instead of their tent means; projection_ridge is its ridge. Off only to
  // measure what it does.
  // Only from kProjectFromSide points a cell side: the projection raises the noise 2.6x, which
  // fewer points do not pay for (measured: the Cornell box at its automatic density and 4 went
  // from 3.2% to 3.6% error; at 10 texels/m and 16, 5.3% to 4.8%).
  bool project_direct = true;
  // The direct term as the ratio estimator (unshadowed_light.h): per texel, the closed-form
  // unshadowed light times the share the shadow rays let through (the estimate over the same
  // estimate with every shadow ray unblocked). Lit and fully shadowed texels lose all noise;
  // only penumbrae keep the shadow rays' noise. Scenes whose lights have more than
  // kMaxAnalyticTriangles triangles keep the plain estimate. Off only to measure what it does.
  bool ratio_estimator = true;
  // The direct term through Open Image Denoise (denoise_texels.h) before its projection: with
  // the ratio estimator only the shadow rays' share is denoised (the noisy factor; the closed
  // form is exact), and only penumbra texels (a share of 0 or 1 has no noise) take OIDN's
  // value; else the whole term. Needs OIDN's library (oidn.h). Measured on PenumbraTexels at 8
  // points a cell side: 1.44% -> 0.96% mean error (1.05% when every texel took OIDN's value).
  bool denoise_direct = false;
  float projection_ridge = 0.1f;
  float seam_weight = 16.0f;
  uint64_t seed = 1;
  // Rings of empty texels filled from the charts: 64, the largest atlas_padding, fills every
  // gutter, so the mip levels an engine builds (level k reads 2^k texels) pull in the chart's
  // own light, not black (the fill stops early where nothing is left to fill).
  int dilation_rings = 64;
  // Contents all, `lightbake export --shard i/n`: bake the direct term of this shard's range of
  // node rows only (texel_footprint.h, partition_texel_rows), 0 elsewhere; each baked node has
  // the bits of the unsharded lightmap's.
  int shard = 0;
  int shard_count = 1;
};

struct Lightmap {
  int width = 0;
  int height = 0;
  LightmapContents contents = LightmapContents::indirect;
  std::vector<vec3> radiance;  // width*height, E/pi, the sum of the terms, dilated
  std::vector<vec3> soft;      // the radiosity term alone (not dilated)
  std::vector<vec3> direct;    // the direct term's tent means (empty for `indirect`): what
                               // shards join; the sum holds it projected
  std::vector<vec3> direct_term;  // the direct term in the sum: the ratio estimator's, projected
  ProjectionStats projection;  // what the direct term's projection did
  bool ratio_estimator = false;  // whether the direct term is the ratio estimator
  bool denoised = false;         // whether the direct term went through the denoiser
  DenoiseStats denoise;          // what the denoiser did
  TexelRows direct_rows;       // the node rows whose direct term this bake holds (a shard's)
  // A shard's: the ratio estimator's denominator at the same points as `direct` (its rows),
  // which the merge takes instead of sampling the light again; else empty.
  std::vector<vec3> direct_unshadowed;
  StitchStats seams;           // what stitching found and did
  uint64_t shadow_rays = 0;
  uint64_t direct_points = 0;  // surface points of the direct term (a shadow ray each, at most)
  double seconds = 0.0;
};

// Per scene mesh, the surface the lightmap's texels lie on: its refined radiosity mesh where it
// has one with lightmap UVs, else the scene mesh as the atlas laid it out (mesh_with_lightmap);
// null without a map. Pointers into `bake` and `storage`.
std::vector<const Mesh*> lightmap_surfaces(const Scene& scene, const BakeResult& bake,
                                           std::vector<Mesh>& storage);

// The direct term's light samples for a cell's n points (every estimator of the direct term
// uses them, so their values agree point for point): the light choice and the point on the
// light stratified over the points, shuffled so they do not correlate with the position in the
// cell. Deterministic per (seed, cell).
struct DirectLightSample {
  float u_select = 0.0f;
  vec2 u_light{0.0f};  // in [0, 1)^2
};
void direct_light_samples(uint64_t seed, size_t cell, size_t n,
                          std::vector<DirectLightSample>& out);

// The direct term's points per cell side: params.direct_side, or the automatic rule's for this
// atlas (direct_side 0). Every fill of the direct term's points must use it.
int direct_side_for(const LightmapParams& params, const TexelFootprints& footprints);

// Throws Cancelled when `progress` is cancelled (only the direct term takes long).
// `direct` (contents all): the direct term already baked, width x height of the atlas (the
// shards' nodes joined by `lightbake merge`); it is used as is instead of being baked.
// `direct_unshadowed` (with `direct`, may be null): its ratio estimator's denominator, joined
// likewise (Lightmap::direct_unshadowed); null: sampled here.
Lightmap bake_lightmap(const Scene& scene, const BakeResult& bake, const LightmapParams& params,
                       const Progress& progress = {}, const std::vector<vec3>* direct = nullptr,
                       const std::vector<vec3>* direct_unshadowed = nullptr);

}  // namespace lb
