// cycles_check IMAGE.exr CYCLES_A.exr CYCLES_B.exr [--expect-ratio R] [--max-energy E]
//              [--max-mre M] [--block N] [--max-noise F] [--evidence DIR NAME]
// A lightbake render against Cycles' render of the same camera (tests/blender/, docs/gltf.md
// "Scenes from Blender, checked against Cycles"). Cycles' image comes as two halves rendered
// with different seeds: their mean is the reference, their difference measures the
// reference's own noise.
//
//   energy  sum of IMAGE / sum of the reference over every pixel and colour channel; within
//           E of R (R: the documented factor where Blender's convention differs from the file's,
//           else 1): |energy / R - 1| <= E. Its noise: the two halves' sums differ by
//           |a - b| / (a + b) of the mean, which is printed (the reference's own error is about
//           half of that).
//   mre     mean relative error |a - b| / (b + eps), eps 1% of the reference's mean (as
//           `lightbake compare`), over N x N pixel blocks (each block's mean, per channel), so
//           that it measures light rather than Cycles' per-pixel noise; <= M when M is given.
//   noise   the reference's own block MRE, estimated as MRE(half a, half b) / 2 (the halves
//           differ by twice the mean's noise), <= F: a check against a reference too noisy
//           for M to mean anything.
// Prints one line; exits 1 when a check fails (writing the evidence of write_comparison into
// DIR when given: NAME.exr/.png is lightbake's image, NAME_ref the reference, at full size),
// 2 on bad input.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "bake/io/image_io.h"
#include "bake/metrics/image_metrics.h"

namespace {

lb::Image rgb(const lb::Image& image) {  // Blender's EXR may carry alpha
  lb::Image out(image.width, image.height, 3);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      for (int c = 0; c < 3; ++c) out.at(x, y, c) = image.at(x, y, std::min(c, image.channels - 1));
  return out;
}

lb::Image mean_of(const lb::Image& a, const lb::Image& b) {
  lb::Image out = a;
  for (size_t i = 0; i < out.pixels.size(); ++i) out.pixels[i] = 0.5f * (a.pixels[i] + b.pixels[i]);
  return out;
}

// Each N x N block's mean (a partial block at the right or bottom edge is dropped).
lb::Image blocks(const lb::Image& image, int n) {
  lb::Image out(image.width / n, image.height / n, 3);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x)
      for (int c = 0; c < 3; ++c) {
        double sum = 0.0;
        for (int j = 0; j < n; ++j)
          for (int i = 0; i < n; ++i) sum += image.at(x * n + i, y * n + j, c);
        out.at(x, y, c) = float(sum / double(n * n));
      }
  return out;
}

double total(const lb::Image& image) {
  double sum = 0.0;
  for (float v : image.pixels) sum += v;
  return sum;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr,
                 "usage: cycles_check IMAGE.exr CYCLES_A.exr CYCLES_B.exr [--expect-ratio R] "
                 "[--max-energy E] [--max-mre M] [--block N] [--max-noise F] "
                 "[--evidence DIR NAME]\n");
    return 2;
  }
  double expect_ratio = 1.0, max_energy = 0.02, max_mre = -1.0, max_noise = 0.02;
  int block = 4;
  std::string evidence_dir, evidence_name;
  for (int i = 4; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool has_value = i + 1 < argc;
    if (arg == "--expect-ratio" && has_value) {
      expect_ratio = std::atof(argv[++i]);
    } else if (arg == "--max-energy" && has_value) {
      max_energy = std::atof(argv[++i]);
    } else if (arg == "--max-mre" && has_value) {
      max_mre = std::atof(argv[++i]);
    } else if (arg == "--block" && has_value) {
      block = std::atoi(argv[++i]);
    } else if (arg == "--max-noise" && has_value) {
      max_noise = std::atof(argv[++i]);
    } else if (arg == "--evidence" && i + 2 < argc) {
      evidence_dir = argv[++i];
      evidence_name = argv[++i];
    } else {
      std::fprintf(stderr, "cycles_check: unknown argument '%s'\n", arg.c_str());
      return 2;
    }
  }
  if (block < 1 || !(expect_ratio > 0.0)) {
    std::fprintf(stderr, "cycles_check: --block must be >= 1 and --expect-ratio > 0\n");
    return 2;
  }
  try {
    const lb::Image image = rgb(lb::read_image(argv[1], lb::ImageDecode::as_stored));
    const lb::Image half_a = rgb(lb::read_image(argv[2], lb::ImageDecode::as_stored));
    const lb::Image half_b = rgb(lb::read_image(argv[3], lb::ImageDecode::as_stored));
    for (const lb::Image* other : {&half_a, &half_b})
      if (other->width != image.width || other->height != image.height) {
        std::fprintf(stderr, "cycles_check: the images differ in size (%dx%d vs %dx%d)\n",
                     image.width, image.height, other->width, other->height);
        return 2;
      }
    const lb::Image reference = mean_of(half_a, half_b);
    const double energy = total(image) / total(reference);
    const double energy_noise =
        std::abs(total(half_a) - total(half_b)) / (total(half_a) + total(half_b));

    const lb::Image image_blocks = blocks(image, block);
    const lb::Image reference_blocks = blocks(reference, block);
    const double mre = lb::compare_to_reference(image_blocks, reference_blocks).mean_relative_error;
    // The halves' own eps: 1% of their mean, as the reference's.
    const double noise =
        0.5 * lb::compare_to_reference(blocks(half_a, block), blocks(half_b, block))
                  .mean_relative_error;

    const bool energy_ok = std::abs(energy / expect_ratio - 1.0) <= max_energy;
    const bool mre_ok = max_mre < 0.0 || mre <= max_mre;
    const bool noise_ok = max_mre < 0.0 || noise <= max_noise;
    char mre_limit[32] = "none";
    if (max_mre >= 0.0) std::snprintf(mre_limit, sizeof mre_limit, "%.3g", max_mre);
    std::printf(
        "%s: energy %.4f of the reference's (expected %.4f, within %.3g: %s; its halves differ "
        "by %.4f), MRE over %dx%d blocks %.4f (limit %s: %s), the reference's own %.4f (limit "
        "%.3g: %s)\n",
        argv[1], energy, expect_ratio, max_energy, energy_ok ? "yes" : "NO", energy_noise, block,
        block, mre, mre_limit, mre_ok ? "yes" : "NO", noise, max_noise,
        max_mre < 0.0 ? "not checked" : noise_ok ? "yes" : "NO");
    const bool pass = energy_ok && mre_ok && noise_ok;
    if (!pass && !evidence_dir.empty())
      std::printf("  evidence: %s\n",
                  lb::write_comparison(evidence_dir, evidence_name, image, reference).c_str());
    return pass ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cycles_check: %s\n", e.what());
    return 2;
  }
}
