#pragma once
// A reference film's exact sums as bytes: the payload of a reference shard (reference_shard.h),
// what `lightbake merge` adds (an image of float averages would lose the bits). Little-endian:
//
//   u32 width, u32 height, u32 half_passes[2], u64 lost_samples,
//   u64 n, n x (u64 pass index, f64 pass mean) in increasing index, then for each half with
//   passes, width x height x 3 fixed-point sums (film.h) as (u64 low, i64 high) words.

#include <cstddef>
#include <vector>

#include "bake/binary_file.h"
#include "bake/reference/film.h"

namespace lb::reference {

std::vector<std::byte> encode_film(const Film& film);
// Throws std::runtime_error naming the reader's file and byte when the data is truncated,
// inconsistent (pass counts, indices out of order) or followed by anything.
Film decode_film(Reader& reader);

}  // namespace lb::reference
