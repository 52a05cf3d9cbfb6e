#pragma once
// Isometric unfolding of thin charts (the atlas's second chart pass, bake/illumination/atlas.h).
// A chart only a few texels wide (one side of a thin table leg, a tabletop's rim) costs more in
// padding than in texels, so the thin charts of a mesh (and the small flat charts next to them)
// are grown again as strips: each new triangle is turned about the edge it shares with the chart
// into the chart's plane (a rigid motion, so lengths, angles and areas stay those of the world:
// stretch 1), and joins only if it overlaps no triangle already there and the chart keeps
// filling most of its rectangle. The four sides of a leg become one strip, a rim a frame around
// its top. Where a strip closes on itself (around a cylinder) a vertex gets two places; the
// atlas splits it like a vertex two charts share.

#include <array>
#include <cstdint>
#include <vector>

#include "bake/scene.h"

namespace lb {

// Regrows the triangles in `seeds` (each seeds a chart in this order unless an earlier one took
// it; growth only joins triangles in `seeds`) as unfolded charts. chart_of (per triangle, -1
// for degenerate ones) gets new chart ids from chart_count on for them, which can leave old
// ids unused; returns the new chart count. corners[t] holds the planar coordinates (metres) of
// triangle t's corners in its unfolded chart, and unfolded[chart] is set for the charts made
// here. `texel` (metres) sets the tolerances. Deterministic: the order is the seeds' and the
// neighbours'.
int unfold_charts(const Mesh& mesh, const std::vector<std::vector<uint32_t>>& neighbours,
                  const std::vector<uint32_t>& seeds, float texel, std::vector<int>& chart_of,
                  int chart_count, std::vector<std::array<vec2, 3>>& corners,
                  std::vector<uint8_t>& unfolded);

}  // namespace lb
