// web_image_diff A.png B.png [--max-mean L] [--max-p99 L] [--evidence DIR NAME]
// Compares two 8-bit sRGB screenshots as they are displayed: per channel |a - b| in 8-bit
// levels. Prints the mean over all channels, the 99th percentile and the maximum over pixels of
// the largest channel difference, and each image's mean level; exits 1 when the mean or the
// percentile is over its limit (then writes the evidence of bake/io/image_io.h's
// write_comparison into DIR when given), 2 on bad input. Used by the three.js check
// (tests/web/run_threejs_check.sh).

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

#include "bake/io/image_io.h"

namespace {

struct Levels {
  double mean = 0.0;  // mean |a - b| over every colour value, 8-bit levels
  int p99 = 0;        // 99th percentile over pixels of the largest channel difference
  int max = 0;
  int max_x = 0, max_y = 0;           // where the largest difference is
  double mean_a = 0.0, mean_b = 0.0;  // mean level of each image (not vacuous: not black)
};

Levels compare(const lb::Image& a, const lb::Image& b) {
  Levels levels;
  std::vector<int> pixel_max;
  pixel_max.reserve(size_t(a.width) * size_t(a.height));
  size_t values = 0;
  for (int y = 0; y < a.height; ++y) {
    for (int x = 0; x < a.width; ++x) {
      int largest = 0;
      for (int c = 0; c < 3; ++c) {
        const int va = int(std::lround(a.at(x, y, c) * 255.0f));
        const int vb = int(std::lround(b.at(x, y, c) * 255.0f));
        largest = std::max(largest, std::abs(va - vb));
        levels.mean += std::abs(va - vb);
        levels.mean_a += va;
        levels.mean_b += vb;
        ++values;
      }
      pixel_max.push_back(largest);
      if (largest > levels.max) {
        levels.max = largest;
        levels.max_x = x;
        levels.max_y = y;
      }
    }
  }
  levels.mean /= double(values);
  levels.mean_a /= double(values);
  levels.mean_b /= double(values);
  std::sort(pixel_max.begin(), pixel_max.end());
  levels.p99 = pixel_max[std::min(pixel_max.size() - 1, size_t(0.99 * double(pixel_max.size())))];
  return levels;
}

lb::Image rgb(const lb::Image& image) {  // drops an alpha channel (the browser's PNG has one)
  lb::Image out(image.width, image.height, 3);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      for (int c = 0; c < 3; ++c) out.at(x, y, c) = image.at(x, y, std::min(c, image.channels - 1));
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr,
                 "usage: web_image_diff A.png B.png [--max-mean L] [--max-p99 L] "
                 "[--evidence DIR NAME]\n");
    return 2;
  }
  double max_mean = 1e9;
  int max_p99 = 1 << 20;
  std::string evidence_dir, evidence_name;
  for (int i = 3; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--max-mean" && i + 1 < argc) {
      max_mean = std::atof(argv[++i]);
    } else if (arg == "--max-p99" && i + 1 < argc) {
      max_p99 = std::atoi(argv[++i]);
    } else if (arg == "--evidence" && i + 2 < argc) {
      evidence_dir = argv[++i];
      evidence_name = argv[++i];
    } else {
      std::fprintf(stderr, "web_image_diff: unknown argument '%s'\n", arg.c_str());
      return 2;
    }
  }
  try {
    const lb::Image a = rgb(lb::read_image(argv[1], lb::ImageDecode::as_stored));
    const lb::Image b = rgb(lb::read_image(argv[2], lb::ImageDecode::as_stored));
    if (a.width != b.width || a.height != b.height) {
      std::fprintf(stderr, "web_image_diff: %s is %dx%d but %s is %dx%d\n", argv[1], a.width,
                   a.height, argv[2], b.width, b.height);
      return 2;
    }
    const Levels d = compare(a, b);
    const bool pass = d.mean <= max_mean && d.p99 <= max_p99;
    std::printf(
        "%s vs %s: mean |diff| %.3f/255 (limit %.3g), p99 %d/255 (limit %d), max %d/255 at "
        "(%d, %d); mean level %.1f vs %.1f: %s\n",
        argv[1], argv[2], d.mean, max_mean, d.p99, max_p99, d.max, d.max_x, d.max_y, d.mean_a,
        d.mean_b, pass ? "within" : "OVER");
    if (!pass && !evidence_dir.empty()) {
      std::printf("  evidence: %s\n",
                  lb::write_comparison(evidence_dir, evidence_name, a, b).c_str());
    }
    return pass ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "web_image_diff: %s\n", e.what());
    return 2;
  }
}
