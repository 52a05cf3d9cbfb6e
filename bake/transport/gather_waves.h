#pragma once
// The final gather (final_gather.h) of many points at once, their rays traced in waves through
// Accel's stream interface: ray k of every point in one wave, then those rays' shadow rays in
// another, where gather_soft_light traces one ray at a time. Each point keeps its own random
// stream and sums its rays in the same order, so a point's result has the bits of
// gather_soft_light(context, x, stream, samples, cell) wherever the stream traversal returns
// the single-ray hit (Accel::intersect_many: all but exact ties).
// Later specular bounces and the backs of two-sided surfaces (rare) go one ray at a time.

#include <cstdint>
#include <span>
#include <vector>

#include "bake/transport/final_gather.h"

namespace lb {

// One point to gather at: the receiver, its random stream and the cell its directions come
// from (gather_soft_light's arguments).
struct GatherPoint {
  ReceiverPoint x;
  uint64_t stream = 0;
  SampleCell cell;
};

// means[p] = gather_soft_light(context, points[p].x, points[p].stream, samples,
// points[p].cell, counts, group_means + p * groups) for every point; with context.groups and a
// non-empty `group_means` (points x groups, point-major) each group's part too.
void gather_soft_light_waves(const GatherContext& context, std::span<const GatherPoint> points,
                             int samples, std::span<vec3> means, GatherCounts& counts,
                             std::span<vec3> group_means = {});

}  // namespace lb
