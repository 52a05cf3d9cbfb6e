#include "bake/reference/film_io.h"

#include <string>

namespace lb::reference {

std::vector<std::byte> encode_film(const Film& film) {
  Writer w;
  w.put(uint32_t(film.width)), w.put(uint32_t(film.height));
  w.put(uint32_t(film.half_passes[0])), w.put(uint32_t(film.half_passes[1]));
  w.put(film.lost_samples);
  w.put(uint64_t(film.pass_indices.size()));
  for (size_t k = 0; k < film.pass_indices.size(); ++k)
    w.put(film.pass_indices[k]), w.put(film.pass_means[k]);
  for (int h = 0; h < 2; ++h) {
    if (film.half_passes[h] == 0) continue;
    for (const FixedPixel& p : film.half[h])
      for (const FixedSum& sum : p.c) w.put(uint64_t(sum)), w.put(int64_t(sum >> 64));
  }
  return w.bytes();
}

Film decode_film(Reader& r) {
  const uint32_t width = r.get<uint32_t>(), height = r.get<uint32_t>();
  if (width < 1 || height < 1 || width > 16384 || height > 16384)
    r.fail("film size " + std::to_string(width) + "x" + std::to_string(height));
  Film film{int(width), int(height)};
  const uint32_t half_passes[2] = {r.get<uint32_t>(), r.get<uint32_t>()};
  film.lost_samples = r.get<uint64_t>();
  const uint64_t n = r.get<uint64_t>();
  if (n != uint64_t(half_passes[0]) + half_passes[1] || n > (uint64_t(1) << 31))
    r.fail("pass list does not match the halves' pass counts");
  uint64_t parity[2] = {0, 0};
  for (uint64_t k = 0; k < n; ++k) {
    const uint64_t index = r.get<uint64_t>();
    if (k > 0 && index <= film.pass_indices.back()) r.fail("pass indices out of order");
    film.pass_indices.push_back(index);
    film.pass_means.push_back(r.get<double>());
    ++parity[index % 2];
  }
  if (parity[0] != half_passes[0] || parity[1] != half_passes[1])
    r.fail("pass indices do not match the halves' pass counts");
  for (int h = 0; h < 2; ++h) {
    film.half_passes[h] = int(half_passes[h]);
    if (half_passes[h] == 0) continue;
    for (FixedPixel& p : film.half[h])
      for (FixedSum& sum : p.c) {
        const uint64_t low = r.get<uint64_t>();
        const int64_t high = r.get<int64_t>();
        sum = FixedSum((unsigned __int128)(uint64_t(high)) << 64 | low);
      }
  }
  r.expect_end();
  return film;
}

}  // namespace lb::reference
