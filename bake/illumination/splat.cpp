#include "bake/illumination/splat.h"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>

namespace lb::illumination {

glm::dvec3 splat(const Atlas& atlas, const Scene& scene,
                 const std::vector<const std::vector<Deposit>*>& blocks,
                 std::vector<glm::dvec3>& node_power, std::vector<double>* node_deposits) {
  struct Splat {
    uint32_t node[4];
    float weight[4];
  };
  constexpr uint32_t unmapped_node = ~uint32_t(0);
  // Groups of about this many deposits reuse one small weights buffer (no page faults).
  constexpr size_t group_deposits = size_t(1) << 15;
  std::vector<Splat> splats;
  std::vector<size_t> offset;
  std::vector<glm::dvec3> unmapped(blocks.size(), glm::dvec3(0.0));
  const size_t nodes = node_power.size();
  const size_t bands = size_t(std::max(1, tbb::this_task_arena::max_concurrency()));
  for (size_t first = 0; first < blocks.size();) {
    size_t last = first, count = 0;
    offset.clear();
    while (last < blocks.size() && (last == first || count < group_deposits)) {
      offset.push_back(count);
      count += blocks[last++]->size();
    }
    if (splats.size() < count) splats.resize(count);
    tbb::parallel_for(first, last, [&](size_t b) {
      const std::vector<Deposit>& deposits = *blocks[b];
      Splat* out = splats.data() + offset[b - first];
      for (size_t k = 0; k < deposits.size(); ++k) {
        const Deposit& d = deposits[k];
        NodeWeights nw;
        if (!node_weights(atlas, scene, d.mesh, d.triangle, d.barycentric, nw)) {
          out[k].node[0] = unmapped_node;
          unmapped[b] += glm::dvec3(d.power);
          continue;
        }
        for (int c = 0; c < 4; ++c) out[k].node[c] = uint32_t(nw.index[c]);
        for (int c = 0; c < 4; ++c) out[k].weight[c] = nw.weight[c];
      }
    });
    tbb::parallel_for(size_t(0), bands, [&](size_t band) {
      const size_t lo = nodes * band / bands, hi = nodes * (band + 1) / bands;
      for (size_t b = first; b < last; ++b) {
        const std::vector<Deposit>& deposits = *blocks[b];
        const Splat* in = splats.data() + offset[b - first];
        for (size_t k = 0; k < deposits.size(); ++k) {
          if (in[k].node[0] == unmapped_node) continue;
          const glm::dvec3 power(deposits[k].power);
          for (int c = 0; c < 4; ++c)
            if (in[k].node[c] >= lo && in[k].node[c] < hi) {
              node_power[in[k].node[c]] += double(in[k].weight[c]) * power;
              if (node_deposits) (*node_deposits)[in[k].node[c]] += double(in[k].weight[c]);
            }
        }
      }
    });
    first = last;
  }
  glm::dvec3 total(0.0);
  for (const glm::dvec3& u : unmapped) total += u;
  return total;
}

}  // namespace lb::illumination
