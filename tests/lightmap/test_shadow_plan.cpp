// The adaptive shadow rays' plan (shadow_plan.h) on a made-up pilot: the budget is kept, the
// penumbra's cells that saw less light trace more rays, and what they leave goes to the dark
// cells nearest them.

#include <gtest/gtest.h>

#include "bake/lightmap/shadow_plan.h"

namespace lb {
namespace {

// A 40 x 10 atlas, a pilot of 4 x 4 rays a cell: every cell lit, but for columns 10..29, whose
// cells saw lit(i) of their 16 rays, from 15 (column 10) down to 1 (column 29) and the
// rest blocked.
PilotOutcome ramp_pilot(int w, int h) {
  PilotOutcome pilot(size_t(w) * size_t(h));
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      const size_t c = size_t(j) * size_t(w) + size_t(i);
      pilot.rays[c] = 16;
      pilot.lit[c] = i < 10 ? 16 : i < 30 ? uint32_t(15 - (i - 10) * 14 / 19) : 16;
      pilot.found[c] = pilot.lit[c] == 16 ? PilotOutcome::kSomeLit
                                          : PilotOutcome::kSomeLit | PilotOutcome::kSomeBlocked;
    }
  return pilot;
}

TEST(ShadowPlan, KeepsTheBudgetAndSpendsMoreWhereLessLightGetsThrough) {
  const int w = 40, h = 10, pilot_side = 4, shadow_side = 8, full_side = 16;
  const PilotOutcome pilot = ramp_pilot(w, h);
  const ShadowPlan plan = adaptive_shadow_plan(w, h, pilot, pilot_side, shadow_side, full_side);
  double rays = 0.0;  // the pilot's and the plan's
  for (size_t c = 0; c < plan.side.size(); ++c) {
    rays += pilot.rays[c];
    const int i = int(c % size_t(w));
    // Columns 10..29 disagree, and 9 and 30 with them: they and two columns around trace.
    const bool traced = i >= 7 && i <= 32;
    EXPECT_EQ(plan.mode[c], traced ? ShadowPlan::kTrace : ShadowPlan::kLit) << "column " << i;
    if (plan.mode[c] == ShadowPlan::kTrace) {
      const int side = plan.side[c] == 0 ? full_side : plan.side[c];
      EXPECT_GE(side, pilot_side);
      rays += double(side) * double(side);
    }
  }
  const double budget = double(w * h) * shadow_side * shadow_side;
  EXPECT_LE(rays, budget);
  EXPECT_GE(rays, 0.9 * budget);  // little of it left unspent
  // Row 5 away from the ramp's ends: the darker a column, the more rays (never fewer).
  auto side_at = [&](int i) {
    const uint8_t s = plan.side[size_t(5) * size_t(w) + size_t(i)];
    return s == 0 ? full_side : int(s);
  };
  for (int i = 12; i < 28; ++i) EXPECT_LE(side_at(i), side_at(i + 1)) << "column " << i;
  EXPECT_LT(side_at(12), side_at(27));
}

// No disagreement anywhere: no cell traces, each keeps the pilot's verdict.
TEST(ShadowPlan, KeepsEveryVerdictWithoutAPenumbra) {
  const int w = 6, h = 4;
  PilotOutcome pilot(size_t(w) * size_t(h));
  for (size_t c = 0; c < pilot.rays.size(); ++c) {
    const bool lit = c % size_t(w) < 3;  // left half lit, right half dark, no cell between
    pilot.rays[c] = 4;
    pilot.lit[c] = lit ? 4 : 0;
    pilot.found[c] = lit ? PilotOutcome::kSomeLit : PilotOutcome::kSomeBlocked;
  }
  pilot.found[0] = 0, pilot.rays[0] = 0, pilot.lit[0] = 0;  // no shadow ray: no verdict
  // The two halves meet: columns 2 and 3 disagree with each other, so they trace.
  const ShadowPlan plan = adaptive_shadow_plan(w, h, pilot, 2, 4, 8);
  for (size_t c = 0; c < plan.mode.size(); ++c)
    EXPECT_EQ(plan.mode[c], c == 0 ? ShadowPlan::kLit : ShadowPlan::kTrace);
  // Apart (a column of cells with no ray between): every lit cell lit, every dark one dark.
  for (size_t c = 2; c < pilot.rays.size(); c += size_t(w))
    pilot.found[c] = 0, pilot.rays[c] = 0, pilot.lit[c] = 0;
  const ShadowPlan apart = adaptive_shadow_plan(w, h, pilot, 2, 4, 8);
  for (size_t c = 0; c < apart.mode.size(); ++c) {
    const size_t i = c % size_t(w);
    EXPECT_EQ(apart.mode[c], i >= 3 ? ShadowPlan::kDark : ShadowPlan::kLit) << c;
  }
}

// What the penumbra leaves of the budget goes to the dark verdicts nearest it. A 60 x 4 atlas, a
// pilot of one ray a cell: columns 0..9 lit, 10..59 blocked. Columns 9 and 10 disagree, so 7..12
// trace (24 cells), every point (4 x 4) since the budget allows it: 24 x 16 rays of the 240 x 4
// (pilot included). The 240 x 3 - 384 = 336 left trace the dark cells at 2 x 2 rays, 4 a cell,
// nearest first: 84 cells, columns 13..33; columns 34..59 keep the dark verdict.
TEST(ShadowPlan, SpendsWhatThePenumbraLeavesOnTheDarkCellsNearestIt) {
  const int w = 60, h = 4;
  PilotOutcome pilot(size_t(w) * size_t(h));
  for (size_t c = 0; c < pilot.rays.size(); ++c) {
    const bool lit = c % size_t(w) < 10;
    pilot.rays[c] = 1;
    pilot.lit[c] = lit ? 1 : 0;
    pilot.found[c] = lit ? PilotOutcome::kSomeLit : PilotOutcome::kSomeBlocked;
  }
  const ShadowPlan plan = adaptive_shadow_plan(w, h, pilot, 1, 2, 4);
  double rays = double(pilot.rays.size());  // the pilot's
  for (size_t c = 0; c < plan.mode.size(); ++c) {
    const int i = int(c % size_t(w));
    const ShadowPlan::Mode expected = i < 7    ? ShadowPlan::kLit
                                      : i < 34 ? ShadowPlan::kTrace
                                               : ShadowPlan::kDark;
    EXPECT_EQ(plan.mode[c], expected) << "column " << i;
    if (plan.mode[c] != ShadowPlan::kTrace) continue;
    EXPECT_EQ(plan.side[c], i <= 12 ? 0 : 2) << "column " << i;  // 0: every point
    rays += i <= 12 ? 16.0 : 4.0;
  }
  EXPECT_EQ(rays, double(w * h) * 4.0);  // the budget, spent to the last ray here
}

}  // namespace
}  // namespace lb
