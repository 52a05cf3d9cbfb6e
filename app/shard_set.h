#pragma once
// The shards given to `lightbake merge` (render tiles or pass-1 ray batches) must be a complete
// set: every index of 0..count-1 exactly once.

#include <cstddef>
#include <string>
#include <vector>

namespace lb::app {

// `indices[k]` is the shard index that the file `paths[k]` reports. Returns, per index, the
// position in `paths` of its file; fail()s naming the file for an index out of range or given
// twice, and names a missing index.
std::vector<size_t> shards_by_index(const std::vector<std::string>& paths,
                                    const std::vector<int>& indices, int count);

}  // namespace lb::app
