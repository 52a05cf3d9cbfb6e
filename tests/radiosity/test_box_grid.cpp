// BoxGrid (bake/box_grid.h): the same ids, in the same order, as testing every box.

#include <gtest/gtest.h>

#include <random>

#include "bake/box_grid.h"

namespace lb {
namespace {

std::vector<uint32_t> brute_force(const std::vector<vec3>& low, const std::vector<vec3>& high,
                                  vec3 qlow, vec3 qhigh) {
  std::vector<uint32_t> ids;
  for (uint32_t i = 0; i < low.size(); ++i)
    if (!glm::any(glm::greaterThan(low[i], high[i])) &&  // empty: never returned
        !glm::any(glm::lessThan(high[i], qlow)) && !glm::any(glm::greaterThan(low[i], qhigh)))
      ids.push_back(i);
  return ids;
}

// Small boxes, floors spanning everything (the large list), flat ones (zero extent in y),
// boxes touching exactly at a face, and empty ones; queries of every size.
TEST(BoxGrid, FindsWhatTestingEveryBoxFinds) {
  std::mt19937 random(7);
  std::uniform_real_distribution<float> at(-10.0f, 10.0f), size(0.0f, 0.5f);
  std::vector<vec3> low, high;
  for (int i = 0; i < 3000; ++i) {
    const vec3 p(at(random), at(random) * 0.1f, at(random));
    const vec3 e(size(random), i % 3 == 0 ? 0.0f : size(random), size(random));
    low.push_back(p);
    high.push_back(p + e);
  }
  low.push_back(vec3(-10.0f, 0.0f, -10.0f)), high.push_back(vec3(10.0f, 0.0f, 10.0f));  // floor
  low.push_back(vec3(1.0f)), high.push_back(vec3(0.0f));                                // empty
  low.push_back(vec3(0.5f, 0.0f, 0.0f)), high.push_back(vec3(1.0f));  // touches the next
  low.push_back(vec3(1.0f, 0.0f, 0.0f)), high.push_back(vec3(2.0f, 1.0f, 1.0f));
  const BoxGrid grid(low, high);
  std::vector<uint32_t> found;
  size_t total = 0;
  for (int q = 0; q < 2000; ++q) {
    const vec3 p(at(random), at(random) * 0.1f, at(random));
    const vec3 e = vec3(size(random), size(random), size(random)) * float(1 + q % 20);
    grid.overlapping(p, p + e, found);
    EXPECT_EQ(found, brute_force(low, high, p, p + e)) << "query " << q;
    total += found.size();
  }
  grid.overlapping(vec3(1.0f, 0.5f, 0.5f), vec3(1.0f, 0.5f, 0.5f), found);  // the shared face
  EXPECT_EQ(found, brute_force(low, high, vec3(1.0f, 0.5f, 0.5f), vec3(1.0f, 0.5f, 0.5f)));
  EXPECT_GE(found.size(), 2u);
  EXPECT_GT(total, 10000u);  // the queries did find boxes (67055 with seed 7)
}

}  // namespace
}  // namespace lb
