#include "bake/illumination/fixed_sums.h"

#include <bit>
#include <cmath>
#include <string>

namespace lb::illumination {

namespace {

[[noreturn]] void overflow(const char* what) {
  throw FixedOverflow(std::string("illumination: the fixed-point sum of ") + what +
                      " overflowed (more than 512x the lights' power on one texel or tally)");
}

}  // namespace

FixedScale fixed_scale(const glm::dvec3& emitted, uint64_t planned_rays) {
  FixedScale scale;
  for (int c = 0; c < 3; ++c)
    scale.power_unit[c] = emitted[c] > 0.0 && std::isfinite(emitted[c])
                              ? std::ldexp(emitted[c], -kPowerUnitBits)
                              : 1.0;  // no light in c: every add is 0
  scale.weight_unit = std::ldexp(1.0, -(62 - int(std::bit_width(planned_rays))));
  return scale;
}

int64_t to_fixed(double value, double unit, const char* what) {
  const double units = std::nearbyint(value / unit);
  constexpr double limit = 0x1p62;
  if (!(units >= -limit && units <= limit)) overflow(what);  // also NaN
  return int64_t(units);
}

void add_checked(int64_t& a, int64_t b, const char* what) {
  if (__builtin_add_overflow(a, b, &a)) overflow(what);
}

void add_checked_atomic(int64_t& a, int64_t b, const char* what) {
  const int64_t before = std::atomic_ref<int64_t>(a).fetch_add(b, std::memory_order_relaxed);
  int64_t after = 0;
  if (__builtin_add_overflow(before, b, &after)) overflow(what);
}

void Pass1Sums::add(const Pass1Sums& other) {
  if (other.node_power.size() != node_power.size() ||
      other.node_weight.size() != node_weight.size() ||
      other.groups() != groups() || other.node_l1.size() != node_l1.size())
    throw std::invalid_argument("illumination: adding pass-1 sums of different atlas sizes");
  for (size_t k = 0; k < node_power.size(); ++k)
    add_checked(node_power[k], other.node_power[k], "texel power");
  for (size_t k = 0; k < node_l1.size(); ++k)
    add_checked(node_l1[k], other.node_l1[k], "texel L1 power");
  group_power.add(other.group_power);
  for (size_t k = 0; k < node_weight.size(); ++k)
    add_checked(node_weight[k], other.node_weight[k], "deposit weights");
  add_tally(other.tally);
}

namespace {

// Adds every field of `o` to `t`'s with add(field, value, name) and count(field, value).
template <class Add, class Count>
void add_fields(FixedTally& t, const FixedTally& o, Add add, Count count) {
  for (int c = 0; c < 3; ++c) {
    add(t.sent[c], o.sent[c], "power sent");
    add(t.deposited[c], o.deposited[c], "power deposited");
    add(t.absorbed[c], o.absorbed[c], "power absorbed");
    add(t.escaped[c], o.escaped[c], "power escaped");
    add(t.direct[c], o.direct[c], "direct power");
    add(t.unmapped[c], o.unmapped[c], "unmapped power");
  }
  count(t.casts, o.casts), count(t.rays, o.rays), count(t.emitter_hits, o.emitter_hits);
}

}  // namespace

void Pass1Sums::add_tally(const FixedTally& o) {
  add_fields(tally, o, add_checked, [](uint64_t& a, uint64_t b) { a += b; });
}

void Pass1Sums::add_tally_atomic(const FixedTally& o) {
  add_fields(tally, o, add_checked_atomic, [](uint64_t& a, uint64_t b) {
    std::atomic_ref<uint64_t>(a).fetch_add(b, std::memory_order_relaxed);
  });
}

}  // namespace lb::illumination
