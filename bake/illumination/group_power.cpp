#include "bake/illumination/group_power.h"

#include <stdexcept>
#include <utility>

#include "bake/illumination/fixed_sums.h"

namespace lb::illumination {

namespace {
constexpr size_t kBlockValues = 3 * GroupPower::kNodesPerBlock;  // 3 channels a node
}  // namespace

GroupPower::GroupPower(size_t nodes, size_t groups)
    : nodes_(nodes),
      groups_(groups),
      blocks_per_group_((nodes + kNodesPerBlock - 1) / kNodesPerBlock),
      blocks_(std::make_unique<std::atomic<int64_t*>[]>(groups * blocks_per_group_)) {
  for (size_t b = 0; b < groups * blocks_per_group_; ++b) blocks_[b].store(nullptr);
}

GroupPower::GroupPower(GroupPower&& other) noexcept
    : nodes_(std::exchange(other.nodes_, 0)),
      groups_(std::exchange(other.groups_, 0)),
      blocks_per_group_(std::exchange(other.blocks_per_group_, 0)),
      blocks_(std::move(other.blocks_)) {}

GroupPower& GroupPower::operator=(GroupPower&& other) noexcept {
  GroupPower moved(std::move(other));
  std::swap(nodes_, moved.nodes_);
  std::swap(groups_, moved.groups_);
  std::swap(blocks_per_group_, moved.blocks_per_group_);
  std::swap(blocks_, moved.blocks_);
  return *this;
}

GroupPower::~GroupPower() {
  if (!blocks_) return;
  for (size_t b = 0; b < groups_ * blocks_per_group_; ++b) delete[] blocks_[b].load();
}

int64_t* GroupPower::block(size_t group, size_t b) {
  std::atomic<int64_t*>& slot = blocks_[group * blocks_per_group_ + b];
  int64_t* existing = slot.load(std::memory_order_acquire);
  if (existing) return existing;
  int64_t* made = new int64_t[kBlockValues]();
  // Another thread may have made it meanwhile: then its block is the one.
  if (slot.compare_exchange_strong(existing, made, std::memory_order_acq_rel)) return made;
  delete[] made;
  return existing;
}

void GroupPower::add_atomic(size_t group, size_t node, int c, int64_t units) {
  int64_t* values = block(group, node / kNodesPerBlock);
  add_checked_atomic(values[3 * (node % kNodesPerBlock) + size_t(c)], units, "texel power");
}

int64_t GroupPower::at(size_t group, size_t node, int c) const {
  const int64_t* values =
      blocks_[group * blocks_per_group_ + node / kNodesPerBlock].load(std::memory_order_acquire);
  return values ? values[3 * (node % kNodesPerBlock) + size_t(c)] : 0;
}

void GroupPower::add(const GroupPower& other) {
  if (other.nodes_ != nodes_ || other.groups_ != groups_)
    throw std::invalid_argument("illumination: adding light groups' sums of different shapes");
  for (size_t b = 0; b < groups_ * blocks_per_group_; ++b) {
    const int64_t* from = other.blocks_[b].load(std::memory_order_acquire);
    if (!from) continue;
    int64_t* to = block(b / blocks_per_group_, b % blocks_per_group_);
    for (size_t k = 0; k < kBlockValues; ++k) add_checked(to[k], from[k], "texel power");
  }
}

}  // namespace lb::illumination
