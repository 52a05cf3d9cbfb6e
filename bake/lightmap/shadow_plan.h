#pragma once
// Where the lightmap's direct term spends its shadow rays (LightmapParams::adaptive_shadow_rays,
// issue 36). A pilot of a few rays a cell finds the penumbrae: the cells whose rays disagree,
// within the cell or with a neighbour's, and the cells within kPenumbraReach of them. They
// trace the rest of the budget, the more the less light the pilot saw around them (below); the
// other cells keep the pilot's verdict, which the ratio estimator makes exact (all lit: the
// closed form; all blocked: 0). What the penumbra leaves of the budget (its cells all at every
// point already) goes to the dark verdicts nearest it (trace_dark_fringe in the .cpp).
//
// A verdict's cell weighs in its texels' ratio by every point's unshadowed estimate (no ray),
// not by the pilot's points: at one ray a cell, a point whose light sample lies behind the
// surface's horizon (a light straddling the plane of a block's side) gave the cell 0 in both
// sums, and a texel whose four cells all drew such a point kept 0 instead of the closed form.
// Both measured on the Cornell box at its automatic density (2 of 4 a side, denoised, against
// all the rays undenoised; four seeds of the direct term, means): 1.235% -> 1.171% (every
// point) -> 1.134% (the fringe) against 1.173% (bench/results/LOG.md, 7 Dec 2026).
//
// Why more rays where less light gets through: the map is judged by its relative error, and a
// cell whose share of the light is p, estimated from n rays, is off by sqrt(p (1 - p) / n) / p
// = sqrt((1 - p) / (p n)) of its value. The sum of that over the cells, for a fixed total of
// rays, is least when n goes as ((1 - p) / p)^(1/3) (Lagrange). p is the pilot's lit share over
// the cell and its eight neighbours (a cell alone may have one ray), (lit + 1/2) / (rays + 1) so
// that it is never 0 or 1. A quarter of the rays, denoised, every penumbra cell at one side ->
// weighted so: PenumbraTexels 0.77% -> 0.67% mean error; the Cornell box at 10 and 20 texels/m
// 9.79% -> 9.81% and 3.23% -> 3.07% (all the rays undenoised: 0.71%, 10.27%, 3.19%;
// bench/results/LOG.md, 7 Dec 2026).

#include <cstdint>
#include <vector>

namespace lb {

// What the pilot's rays found in each cell of a width x height atlas.
struct PilotOutcome {
  static constexpr uint8_t kSomeLit = 1, kSomeBlocked = 2;
  std::vector<uint8_t> found;  // kSomeLit | kSomeBlocked; 0: the cell traced no shadow ray
  std::vector<uint32_t> rays;  // shadow rays traced
  std::vector<uint32_t> lit;   // of them, not blocked
  explicit PilotOutcome(size_t cells = 0) : found(cells, 0), rays(cells, 0), lit(cells, 0) {}
};

// Per cell, how the direct term's shadow rays go: `side` x `side` of the points trace one (0:
// every point), or, in mode kLit or kDark, none: the cell keeps the pilot's verdict, and its
// `side` (0) is that of the points its unshadowed estimate is made from.
struct ShadowPlan {
  enum Mode : uint8_t { kTrace, kLit, kDark };
  std::vector<uint8_t> side;
  std::vector<Mode> mode;
};

// Cells within this many of a pilot's disagreement trace. A pilot of few rays a cell reads a
// cell a shadow's edge barely crosses as wholly lit or dark, and a wrong verdict is kept exact
// (never denoised); two cells catch more of them than one (measured with even sides, before
// the weighting below: the Cornell box at 10 texels/m, a quarter of the rays denoised: 10.71%
// -> 9.83% against all of them undenoised 10.27%; three cells spread the budget too thin at 20
// texels/m and in the closed-form penumbra; bench/results/LOG.md).
inline constexpr int kPenumbraReach = 2;

// The plan for shadow_side^2 rays a cell on average, after a pilot of pilot_side^2 a cell: the
// budget is what every cell at shadow_side would trace, the pilot's rays times (shadow_side /
// pilot_side)^2 (a cell part-covered has points, and rays, in proportion to its surface); the
// penumbra's cells share what the pilot left, each side between pilot_side and full_side (every
// point), the largest sides in proportion to the weight above whose rays fit the budget; what
// they leave goes to the cells with a dark verdict, nearest the penumbra first, at shadow_side
// each, while it lasts (an umbra's fringe, where a share of a few percent reads as dark to a
// pilot of one ray a cell: 0, the largest relative error a texel can have). The pilot's rays
// count in the cells that trace again (bake_lightmap), so they are not spent twice.
ShadowPlan adaptive_shadow_plan(int width, int height, const PilotOutcome& pilot, int pilot_side,
                                int shadow_side, int full_side);

}  // namespace lb
