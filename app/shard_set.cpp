#include "app/shard_set.h"

#include <limits>

#include "app/commands.h"

namespace lb::app {

std::vector<size_t> shards_by_index(const std::vector<std::string>& paths,
                                    const std::vector<int>& indices, int count) {
  constexpr size_t none = std::numeric_limits<size_t>::max();
  std::vector<size_t> by_index(size_t(count), none);
  for (size_t k = 0; k < paths.size(); ++k) {
    const int index = indices[k];
    if (index < 0 || index >= count)
      fail(paths[k] + ": shard " + std::to_string(index) + " of " + std::to_string(count));
    if (by_index[size_t(index)] != none)
      fail(paths[k] + ": shard " + std::to_string(index) + " given twice (also " +
           paths[by_index[size_t(index)]] + ")");
    by_index[size_t(index)] = k;
  }
  for (int i = 0; i < count; ++i)
    if (by_index[size_t(i)] == none)
      fail("shard " + std::to_string(i) + " of " + std::to_string(count) + " is missing");
  return by_index;
}

}  // namespace lb::app
