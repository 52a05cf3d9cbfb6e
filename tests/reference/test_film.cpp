// The reference film's fixed-point sums (bake/reference/film.h): passes added in any order and
// in shards give the same bits, values in range are exact, the bounds hold, and the part-file
// bytes (film_io.h) give back the same film.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "bake/reference/film.h"
#include "bake/reference/film_io.h"
#include "bake/sampling.h"
#include "test_helpers.h"

namespace lb::reference {
namespace {

constexpr int kWidth = 7, kHeight = 5;

// A pass's estimate spanning 12 decades (1e-6 to 1e6 W/(sr m^2)): a float sum over it would
// round differently in every order.
std::vector<vec3> estimate(uint64_t pass) {
  Rng rng(hash_seed(11, pass, 0));
  std::vector<vec3> values(size_t(kWidth * kHeight));
  for (vec3& v : values)
    for (int c = 0; c < 3; ++c) v[c] = std::pow(10.0f, -6.0f + 12.0f * rng.next_float());
  return values;
}

bool same_film(const Film& a, const Film& b) {
  bool same = a.passes() == b.passes() && a.pass_indices == b.pass_indices &&
              test::same_bits(a.pass_means, b.pass_means) && a.lost_samples == b.lost_samples;
  for (int h = 0; h < 2; ++h)
    for (size_t i = 0; same && i < a.half[h].size(); ++i)
      for (int c = 0; c < 3; ++c) same = same && a.half[h][i].c[c] == b.half[h][i].c[c];
  return same;
}

TEST(ReferenceFilm, ShardsOfPassesInAnyOrderGiveTheBitsOfTheWholeFilm) {
  constexpr int kPasses = 9;
  Film whole(kWidth, kHeight);
  for (int k = 0; k < kPasses; ++k) whole.add_pass(uint64_t(k), estimate(uint64_t(k)));
  // Three shards (k mod 3), each rendered backwards, added in the order 2, 0, 1.
  Film shard[3] = {Film(kWidth, kHeight), Film(kWidth, kHeight), Film(kWidth, kHeight)};
  for (int k = kPasses - 1; k >= 0; --k) shard[k % 3].add_pass(uint64_t(k), estimate(uint64_t(k)));
  Film merged(kWidth, kHeight);
  for (int s : {2, 0, 1}) merged.add(shard[s]);
  EXPECT_TRUE(same_film(whole, merged));
  EXPECT_TRUE(test::same_bits(whole.average(), merged.average()));
  EXPECT_EQ(whole.noise().pixel_relative_standard_error,
            merged.noise().pixel_relative_standard_error);
  EXPECT_EQ(whole.noise().mean_relative_standard_error,
            merged.noise().mean_relative_standard_error);
  EXPECT_EQ(whole.half_passes[0], 5);  // passes 0, 2, 4, 6, 8
  EXPECT_EQ(whole.half_passes[1], 4);

  // The average is the mean of the passes, computed independently in long double: within a
  // float's rounding (one ulp).
  const std::vector<vec3> average = whole.average();
  for (size_t i = 0; i < average.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      long double sum = 0.0L;
      for (int k = 0; k < kPasses; ++k) sum += estimate(uint64_t(k))[i][c];
      const float expected = float(sum / kPasses);
      EXPECT_LE(std::abs(average[i][c] - expected), std::nextafter(expected, 1e30f) - expected)
          << i << " " << c;
    }
}

TEST(ReferenceFilm, ValuesInRangeAreExactAndOutOfRangeOnesAreLostSamples) {
  // Every float from 2^-37 W/(sr m^2) up is a whole number of 2^-60 units.
  for (float v : {std::ldexp(1.0f, -37), 1.0e-11f, 0.1f, 3.14159f, 6.0e10f,
                  std::nextafter(std::ldexp(1.0f, kMaxValueBits), 0.0f)})
    EXPECT_EQ(from_fixed_radiance(to_fixed_radiance(v)), double(v)) << v;
  // Below, the rounding is half a unit at most: 4.3e-19 W/(sr m^2).
  const float tiny = 1.0e-13f;
  EXPECT_LE(std::abs(from_fixed_radiance(to_fixed_radiance(tiny)) - double(tiny)),
            std::ldexp(1.0, -61));

  Film film(2, 1);
  const float bound = std::ldexp(1.0f, kMaxValueBits);  // 6.9e10 W/(sr m^2)
  film.add_pass(0, {vec3(std::nextafter(bound, 0.0f)), vec3(bound, 1.0f, 1.0f)});
  film.add_pass(1, {vec3(NAN), vec3(2.0f)});
  EXPECT_EQ(film.lost_samples, 2u);
  const std::vector<vec3> average = film.average();
  EXPECT_EQ(average[0].x, std::nextafter(bound, 0.0f) / 2.0f);  // the NaN pass added 0
  EXPECT_EQ(average[1].x, 1.0f);                                // the bound's pass added 0
  // The worst sum 2^31 passes could reach stays inside 128 bits (film.h's range).
  const FixedSum largest = to_fixed_radiance(std::nextafter(bound, 0.0f));
  EXPECT_LT(double(largest) * std::ldexp(1.0, 31), std::ldexp(1.0, 127));
}

TEST(ReferenceFilm, RefusesAPassTwice) {
  Film a(kWidth, kHeight), b(kWidth, kHeight);
  a.add_pass(3, estimate(3));
  EXPECT_THROW(a.add_pass(3, estimate(3)), std::invalid_argument);
  b.add_pass(3, estimate(3));
  EXPECT_THROW(a.add(b), std::invalid_argument);
  EXPECT_THROW(a.add(Film(kWidth + 1, kHeight)), std::invalid_argument);
}

TEST(ReferenceFilm, PartFileBytesGiveBackTheFilm) {
  Film film(kWidth, kHeight);
  for (uint64_t k : {1u, 4u, 7u}) film.add_pass(k, estimate(k));
  film.half[1][0].c[2] = -(FixedSum(1) << 100);  // both 64-bit words and the sign survive
  const std::string path =
      (std::filesystem::path(test::fresh_dir("reference", "film_io")) / "part.refshard").string();
  const std::vector<std::byte> bytes = encode_film(film);
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  Reader reader(path);
  EXPECT_TRUE(same_film(decode_film(reader), film));
  // Truncated: refused, naming the file.
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size() - 1));
  Reader truncated(path);
  try {
    decode_film(truncated);
    ADD_FAILURE() << "a truncated film was read";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("part.refshard: at byte"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace lb::reference
