#include "bake/illumination/splat.h"

namespace lb::illumination {

bool splat_deposit(const Atlas& atlas, const Scene& scene, const FixedScale& scale, uint32_t mesh,
                   uint32_t triangle, vec2 barycentric, vec3 power, Pass1Sums& sums,
                   int group, const std::array<vec3, 3>* l1) {
  NodeWeights nw;
  if (!node_weights(atlas, scene, mesh, triangle, barycentric, nw)) return false;
  for (int corner = 0; corner < 4; ++corner) {
    const double w = double(nw.weight[corner]);
    if (w == 0.0) continue;
    const size_t node = nw.index[corner];
    for (int c = 0; c < 3; ++c)
      if (const int64_t units = to_fixed(w * double(power[c]), scale.power_unit[c], "texel power")) {
        add_checked_atomic(sums.node_power[3 * node + size_t(c)], units, "texel power");
        if (group >= 0) sums.group_power.add_atomic(size_t(group), node, c, units);
      }
    if (l1 && !sums.node_l1.empty())
      for (int a = 0; a < 3; ++a)
        for (int c = 0; c < 3; ++c)
          if (const int64_t units =
                  to_fixed(w * double((*l1)[size_t(a)][c]), scale.power_unit[c], "texel L1 power"))
            add_checked_atomic(sums.node_l1[9 * node + size_t(3 * a + c)], units, "texel L1 power");
    add_checked_atomic(sums.node_weight[node], to_fixed(w, scale.weight_unit, "deposit weights"),
                       "deposit weights");
  }
  return true;
}

}  // namespace lb::illumination
