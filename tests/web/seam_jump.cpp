// seam_jump IMAGE.png COLUMN ROWS MAX_RATIO
// The step a vertical chart seam leaves in a screenshot, against the surface's own gradient:
// with L a pixel's mean level (8-bit, as displayed), the seam's jump is the mean over ROWS of
// |L(COLUMN) - L(COLUMN - 1)| (the seam lies between those columns), the interior gradient the
// mean of |L(x + 1) - L(x)| over the same rows for the six pixel pairs left of it (x = COLUMN
// - 8 .. COLUMN - 3) and six right of it (x = COLUMN + 1 .. COLUMN + 6). A seam whose two sides
// agree under bilinear filtering steps like any pair of pixels (ratio ~1); an unstitched one
// adds its disagreement. ROWS: "a-b,c-d" (inclusive). Prints both and their ratio; exits 1
// when the ratio exceeds MAX_RATIO, 2 on bad input. Used by the three.js check (issue 36:
// "seam jumps in three.js screenshots no larger than 1.2x the interior gradient").

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "bake/io/image_io.h"

namespace {

std::vector<std::pair<int, int>> parse_rows(const std::string& text) {
  std::vector<std::pair<int, int>> ranges;
  std::istringstream in(text);
  for (std::string range; std::getline(in, range, ',');) {
    int a = 0, b = 0;
    char dash = 0;
    std::istringstream r(range);
    if (!(r >> a >> dash >> b) || dash != '-' || a > b) throw std::runtime_error("rows: " + text);
    ranges.emplace_back(a, b);
  }
  return ranges;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 5) {
    std::fprintf(stderr, "usage: seam_jump IMAGE.png COLUMN ROWS(a-b,c-d) MAX_RATIO\n");
    return 2;
  }
  try {
    const lb::Image image = lb::read_image(argv[1]);
    const int column = std::atoi(argv[2]);
    const double max_ratio = std::atof(argv[4]);
    auto level = [&](int x, int y) {
      double sum = 0.0;
      for (int c = 0; c < 3; ++c) sum += std::lround(image.at(x, y, c) * 255.0f);
      return sum / 3.0;
    };
    if (column - 8 < 0 || column + 7 >= image.width)
      throw std::runtime_error("column " + std::to_string(column) + " too near the edge");
    double jump = 0.0, interior = 0.0;
    size_t rows = 0, pairs = 0;
    for (const auto& [first, last] : parse_rows(argv[3]))
      for (int y = first; y <= last; ++y) {
        if (y < 0 || y >= image.height) throw std::runtime_error("row outside the image");
        jump += std::abs(level(column, y) - level(column - 1, y));
        ++rows;
        for (int x = column - 8; x <= column + 6; ++x) {
          if (x >= column - 2 && x <= column) continue;  // the seam's own pair and its neighbours
          interior += std::abs(level(x + 1, y) - level(x, y));
          ++pairs;
        }
      }
    if (rows == 0) throw std::runtime_error("no rows");
    jump /= double(rows);
    interior /= double(pairs);
    const double ratio = interior > 0.0 ? jump / interior : (jump > 0.0 ? INFINITY : 1.0);
    const bool within = ratio <= max_ratio;
    std::printf("%s: seam at column %d: jump %.3f levels, interior gradient %.3f, ratio %.2f "
                "(limit %.2f): %s\n",
                argv[1], column, jump, interior, ratio, max_ratio, within ? "within" : "OVER");
    return within ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "seam_jump: %s\n", e.what());
    return 2;
  }
}
