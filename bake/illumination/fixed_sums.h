#pragma once
// Pass 1's sums in fixed point (issue 16): every deposit's power is rounded once to an integer
// number of units and added to int64 accumulators. Integer addition is associative, so the sums
// have the same bits whatever the order of the adds: any thread count, and any split of the
// blocks into shards whose sums are added later (lightbake bake --shard, lightbake merge).
//
// Scales, chosen from the scene and settings alone (every shard finds the same):
//  - power, per channel c: one unit = P_c * 2^-kPowerUnitBits W, P_c the power of every light
//    pass 1 traces (LightSetup::power summed, W). A node or tally can hold 2^63 units =
//    2^(63 - 54) = 512 P_c before it overflows: a node never receives more than the power sent
//    in expectation (<= P_c; glossy weights above 1 are paid back by others below), so 512 P_c
//    is a margin no real bake nears. Rounding: at most half a unit, 2^-55 P_c = 2.8e-17 P_c,
//    per add. A standard bake's dense ray carries 1.06e-7 = 2^-23.2 of its light's power (9.4 M
//    rays a light: 48^2 sub-zones of 64^2), whose float ulp is 2^-47 of it: the rounding is
//    1/256 of a float ulp of one ray's power with one light, 1/64 at --quality final (4x the
//    rays); with L lights of equal power it grows L-fold (one ulp at ~250 lights standard, ~60
//    final), while a node sums thousands of rays: the maps (float) cannot see it.
//  - deposit weight (the density filter's count): one unit = 2^-k with k = 62 - bit_width(N),
//    N the dense rays planned; each ray deposits at most once with weights summing to 1, so a
//    node holds at most N <= 2^bit_width(N) = 2^(62 - k) units' worth: no overflow. Rounding
//    2^-(k+1) per weight: 2^-36 at N = 1e8 rays (k = 35), far below a float weight's 2^-24.
// An add that would overflow all the same throws OverflowError (never wraps silently).

#include <atomic>
#include <cstdint>
#include <glm/glm.hpp>
#include <stdexcept>
#include <vector>

#include "bake/illumination/group_power.h"

namespace lb::illumination {

constexpr int kPowerUnitBits = 54;

struct FixedScale {
  glm::dvec3 power_unit{1.0};  // W per unit, per channel
  double weight_unit = 1.0;    // deposit weight per unit
};

// `emitted`: W per channel of every light pass 1 traces; `planned_rays`: its dense rays.
FixedScale fixed_scale(const glm::dvec3& emitted, uint64_t planned_rays);

class FixedOverflow : public std::overflow_error {
 public:
  using std::overflow_error::overflow_error;
};

// value / unit rounded to the nearest integer; throws FixedOverflow if it is not finite or
// beyond +-2^62 units (`what` names the quantity).
int64_t to_fixed(double value, double unit, const char* what);

// a += b, throwing FixedOverflow instead of wrapping.
void add_checked(int64_t& a, int64_t b, const char* what);
// The same on an accumulator other threads add to (relaxed: only the final sum is read, after
// the threads are joined).
void add_checked_atomic(int64_t& a, int64_t b, const char* what);

// Per-channel power tallies in units (bake_result.h's IlluminationStats, in fixed point).
struct FixedTally {
  int64_t sent[3] = {}, deposited[3] = {}, absorbed[3] = {}, escaped[3] = {}, direct[3] = {};
  int64_t unmapped[3] = {};  // deposited on meshes the atlas left out (booked as absorbed)
  uint64_t casts = 0, rays = 0, emitter_hits = 0;
};

// Everything the dense rays of pass 1 add up: per atlas node, power (3 channels, node-major)
// and deposit weight; and the tallies. Shards' sums add into the whole pass's.
struct Pass1Sums {
  std::vector<int64_t> node_power;   // 3 * nodes, units of FixedScale::power_unit
  std::vector<int64_t> node_weight;  // nodes, units of FixedScale::weight_unit
  // Light groups (bake/light_groups.h): per group, the power its lights' deposits brought;
  // no groups without them. Each deposit adds the same rounded units there as to node_power.
  GroupPower group_power;
  // Directional maps (IlluminationParams::directional): per node, the L1 band's power-weighted
  // tangential vectors (9 per node: axis-major x, y, z, each RGB), units of power_unit; else
  // empty.
  std::vector<int64_t> node_l1;
  FixedTally tally;

  explicit Pass1Sums(size_t nodes = 0, size_t groups = 0, bool directional = false)
      : node_power(3 * nodes, 0), node_weight(nodes, 0), group_power(nodes, groups),
        node_l1(directional ? 9 * nodes : 0, 0) {}
  size_t nodes() const { return node_weight.size(); }
  size_t groups() const { return group_power.groups(); }
  // Adds `other` (same node count, else std::invalid_argument), overflow-checked.
  void add(const Pass1Sums& other);
  void add_tally(const FixedTally& other);  // overflow-checked
  // Adds a block's tallies from other threads.
  void add_tally_atomic(const FixedTally& block);
};

}  // namespace lb::illumination
