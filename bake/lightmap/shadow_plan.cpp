#include "bake/lightmap/shadow_plan.h"

#include <algorithm>
#include <cmath>

namespace lb {

namespace {

// The rays the penumbra left (`spare`, in the budget's count) go to the cells with a dark
// verdict nearest a penumbra cell (Chebyshev distance in cells, then the cell's index), each at
// shadow_side, while they last: an umbra's fringe lets a little light through (a share of a few
// percent), which a pilot of one ray a cell reads as dark and a dark verdict keeps at 0, the
// largest relative error a texel can have. Nothing without a penumbra.
void trace_dark_fringe(int w, int h, const PilotOutcome& pilot,
                       const std::vector<uint8_t>& penumbra, double spare, int pilot_side,
                       int shadow_side, int full_side, ShadowPlan& plan) {
  const int side = std::min(shadow_side, full_side);
  if (side <= pilot_side) return;
  const size_t cells = size_t(w) * size_t(h);
  std::vector<int> distance(cells, -1);
  std::vector<size_t> ring, next;
  for (size_t c = 0; c < cells; ++c)
    if (penumbra[c]) distance[c] = 0, ring.push_back(c);
  std::vector<size_t> fringe;  // dark cells, nearest first (rings in index order)
  for (int d = 1; !ring.empty(); ++d) {
    next.clear();
    for (const size_t c : ring) {
      const int i = int(c % size_t(w)), j = int(c / size_t(w));
      for (int nj = std::max(0, j - 1); nj <= std::min(h - 1, j + 1); ++nj)
        for (int ni = std::max(0, i - 1); ni <= std::min(w - 1, i + 1); ++ni) {
          const size_t n = size_t(nj) * size_t(w) + size_t(ni);
          if (distance[n] >= 0) continue;
          distance[n] = d;
          next.push_back(n);
        }
    }
    std::sort(next.begin(), next.end());
    for (const size_t c : next)
      if (plan.mode[c] == ShadowPlan::kDark) fringe.push_back(c);
    ring.swap(next);
  }
  const double scale = double(side) / double(pilot_side);
  for (const size_t c : fringe) {
    const double rays = scale * scale * pilot.rays[c];
    if (rays > spare) break;
    spare -= rays;
    plan.mode[c] = ShadowPlan::kTrace;
    plan.side[c] = uint8_t(side >= full_side ? 0 : side);
  }
}

}  // namespace

ShadowPlan adaptive_shadow_plan(int width, int height, const PilotOutcome& pilot, int pilot_side,
                                int shadow_side, int full_side) {
  const int w = width, h = height;
  const size_t cells = size_t(w) * size_t(h);
  const std::vector<uint8_t>& outcome = pilot.found;
  auto index = [w](int i, int j) { return size_t(j) * size_t(w) + size_t(i); };
  // Whether `test` holds for cell (i, j) or a cell within `reach` cells of it.
  auto around = [w, h, &index](int i, int j, int reach, const auto& test) {
    for (int nj = std::max(0, j - reach); nj <= std::min(h - 1, j + reach); ++nj)
      for (int ni = std::max(0, i - reach); ni <= std::min(w - 1, i + reach); ++ni)
        if (test(index(ni, nj))) return true;
    return false;
  };
  constexpr uint8_t kBoth = PilotOutcome::kSomeLit | PilotOutcome::kSomeBlocked;
  std::vector<uint8_t> mixed(cells, 0), penumbra(cells, 0);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      const uint8_t here = outcome[index(i, j)];
      mixed[index(i, j)] = here == kBoth || (here && around(i, j, 1, [&](size_t n) {
                                               return outcome[n] && outcome[n] != here;
                                             }));
    }
  // The penumbra's cells and their weights ((1 - p) / p)^(1/3) (the header).
  std::vector<double> weight(cells, 0.0);
  double pilot_rays = 0.0, min_weight = 1.0;
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      const size_t c = index(i, j);
      pilot_rays += pilot.rays[c];
      penumbra[c] = outcome[c] != 0 &&
                    around(i, j, kPenumbraReach, [&](size_t n) { return mixed[n] != 0; });
      if (!penumbra[c]) continue;
      double rays = 0.0, lit = 0.0;
      around(i, j, 1, [&](size_t n) {
        rays += pilot.rays[n], lit += pilot.lit[n];
        return false;
      });
      const double p = (lit + 0.5) / (rays + 1.0);
      weight[c] = std::cbrt((1.0 - p) / p);
      min_weight = std::min(min_weight, weight[c]);
    }
  const double scale = double(shadow_side) / double(pilot_side);
  const double left = std::max(0.0, pilot_rays * (scale * scale - 1.0));
  // Cell c's side for a factor k: rays in proportion to k x weight, a whole side in range.
  auto side_at = [&](double k, size_t c) {
    return std::clamp(int(double(pilot_side) * std::sqrt(k * weight[c])), pilot_side, full_side);
  };
  auto rays_at = [&](double k) {
    double rays = 0.0;
    for (size_t c = 0; c < cells; ++c)
      if (penumbra[c]) {
        const double r = double(side_at(k, c)) / double(pilot_side);
        rays += r * r * pilot.rays[c];
      }
    return rays;
  };
  // The largest k within the budget (bisection: the rays grow with k; at `high` every
  // penumbra cell traces every point).
  const double full = double(full_side) / double(pilot_side);
  double low = 0.0, high = full * full / min_weight + 1.0;
  for (int step = 0; step < 48; ++step) {
    const double middle = 0.5 * (low + high);
    (rays_at(middle) <= left ? low : high) = middle;
  }
  ShadowPlan plan;
  plan.side.assign(cells, 0);  // a verdict's estimate: every point, no ray (the header)
  plan.mode.assign(cells, ShadowPlan::kLit);
  for (size_t c = 0; c < cells; ++c) {
    if (penumbra[c]) {
      const int side = side_at(low, c);
      plan.side[c] = uint8_t(side >= full_side ? 0 : side);
      plan.mode[c] = ShadowPlan::kTrace;
    } else if (outcome[c] == PilotOutcome::kSomeBlocked) {
      plan.mode[c] = ShadowPlan::kDark;
    }
  }
  trace_dark_fringe(w, h, pilot, penumbra, left - rays_at(low), pilot_side, shadow_side,
                    full_side, plan);
  return plan;
}

}  // namespace lb
