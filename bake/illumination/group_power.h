#pragma once
// Light groups' texel power in pass 1 (bake/light_groups.h): per group, what
// Pass1Sums::node_power holds for every light, from that group's lights alone, in the same
// fixed-point units (fixed_sums.h), so the groups sum to node_power exactly. Held in blocks of
// kNodesPerBlock nodes, each made on the first deposit it receives: caustics reach few texels,
// and a dense array per group cost 24 B a texel (four groups on bench/light_groups.py's room,
// 1373 x 796 texels: 100 MiB; the blocks its caustics touch: under 1 MiB).

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>

namespace lb::illumination {

class GroupPower {
 public:
  static constexpr size_t kNodesPerBlock = 256;

  explicit GroupPower(size_t nodes = 0, size_t groups = 0);
  GroupPower(GroupPower&& other) noexcept;
  GroupPower& operator=(GroupPower&& other) noexcept;
  ~GroupPower();

  size_t groups() const { return groups_; }
  size_t nodes() const { return nodes_; }
  // Adds `units` to channel c of `node` in `group`'s sums, throwing FixedOverflow instead of
  // wrapping; safe from many threads at once (the same bits whatever their order).
  void add_atomic(size_t group, size_t node, int c, int64_t units);
  // The units of channel c of `node` in `group`'s sums (0 where no deposit came).
  int64_t at(size_t group, size_t node, int c) const;
  // Adds `other` (same nodes and groups, else std::invalid_argument), overflow-checked.
  void add(const GroupPower& other);

 private:
  int64_t* block(size_t group, size_t b);  // made (zeros) on first use
  size_t nodes_ = 0, groups_ = 0, blocks_per_group_ = 0;
  std::unique_ptr<std::atomic<int64_t*>[]> blocks_;  // [group * blocks_per_group_ + b]
};

}  // namespace lb::illumination
