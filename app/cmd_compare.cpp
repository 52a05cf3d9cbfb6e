// `lightbake compare A.exr B.exr [--mask M.png] [--region x0,y0,x1,y1] [--subtract C.exr]
// [--error-image E.png|E.exr]`: error metrics of image A against the reference B (or B - C),
// as one JSON line on stdout. Definitions in bake/metrics/image_metrics.h.

#include <cctype>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>

#include "app/commands.h"
#include "app/output_path.h"
#include "app/radiance_output.h"
#include "bake/io/image_io.h"
#include "bake/metrics/error_image.h"
#include "bake/metrics/image_metrics.h"

namespace lb::app {

namespace {

struct CompareOptions {
  std::string image_path;
  std::string reference_path;
  std::string mask_path;
  std::string region;
  std::string subtract_path;
  std::string error_image_path;
  bool force = false;
  double error_max = 0.5;
  double epsilon_fraction = 0.01;
  double epsilon = 0.0;
};

Image read_or_exit(const std::string& path) {
  try {
    return read_image(path, ImageDecode::as_stored);
  } catch (const std::exception& e) {
    fail(e.what());
  }
}

// The library checks too; checking here puts the file names in the message.
void require_same_size(const Image& image, const std::string& path, const Image& first,
                       const std::string& first_path) {
  if (image.width != first.width || image.height != first.height)
    fail(path + ": size " + std::to_string(image.width) + "x" + std::to_string(image.height) +
         " differs from " + first_path + " (" + std::to_string(first.width) + "x" +
         std::to_string(first.height) + ")");
}

void run_compare(const CompareOptions& options) {
  const std::string error_ext = lowercase_extension(options.error_image_path);
  if (!options.error_image_path.empty() && error_ext != ".png" && error_ext != ".exr")
    fail(options.error_image_path + ": --error-image must be .png (false colour) or .exr");
  if (options.error_max <= 0.0) fail("--error-max: must be > 0");
  try {
    if (!options.error_image_path.empty())
      prepare_output_file(options.error_image_path, options.force);
  } catch (const std::exception& e) {
    fail(e.what());
  }
  if (options.epsilon_fraction <= 0.0 && options.epsilon <= 0.0)
    fail("--epsilon-fraction: must be > 0 (or give --epsilon)");

  CompareParams params;
  params.epsilon_fraction = options.epsilon_fraction;
  params.epsilon = options.epsilon;
  if (!options.region.empty()) {
    try {
      params.region = parse_region(options.region);
    } catch (const std::exception& e) {
      fail(e.what());
    }
  }
  const Image image = read_or_exit(options.image_path);
  Image reference = read_or_exit(options.reference_path);
  require_same_size(reference, options.reference_path, image, options.image_path);
  if (!options.subtract_path.empty()) {
    const Image other = read_or_exit(options.subtract_path);
    require_same_size(other, options.subtract_path, image, options.image_path);
    reference = subtract_images(reference, other);
  }
  Image mask;
  if (!options.mask_path.empty()) {
    mask = read_or_exit(options.mask_path);
    require_same_size(mask, options.mask_path, image, options.image_path);
    params.mask = &mask;
  }

  ImageMetrics metrics;
  try {
    metrics = compare_to_reference(image, reference, params);
  } catch (const std::invalid_argument& e) {
    fail(options.image_path + " vs " + options.reference_path + ": " + e.what());
  }
  if (!options.error_image_path.empty()) {
    const Image error = relative_error_image(image, reference, params, metrics.epsilon);
    if (error_ext == ".exr")
      write_exr(options.error_image_path, error, ExrPixelType::float32);
    else
      write_png(options.error_image_path, false_colour_image(error, options.error_max));
  }
  std::printf("%s\n", metrics_json(metrics).c_str());
}

}  // namespace

void register_compare(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "compare", "Error metrics of image A against a reference B, as one JSON line on stdout");
  auto options = std::make_shared<CompareOptions>();
  cmd->add_option("image", options->image_path, "Image A (linear EXR)")->required();
  cmd->add_option("reference", options->reference_path, "Reference B (linear EXR)")->required();
  cmd->add_option("--mask", options->mask_path,
                  "Image of the same size; pixels whose first channel is > 0.5 are compared");
  cmd->add_option("--region", options->region,
                  "Compare only pixels x0 <= x < x1, y0 <= y < y1 (origin top left)");
  cmd->add_option("--subtract", options->subtract_path,
                  "Compare A against B minus this image (per-term comparisons)");
  cmd->add_flag("--force", options->force,
                "Replace the error image even if lightbake did not write it");
  cmd->add_option("--error-image", options->error_image_path,
                  "Write the per-pixel relative error: .png false colour, .exr raw values");
  cmd->add_option("--error-max", options->error_max,
                  "Relative error shown as the brightest colour in a PNG error image");
  cmd->add_option("--epsilon-fraction", options->epsilon_fraction,
                  "eps for dark pixels as a fraction of the reference's mean");
  cmd->add_option("--epsilon", options->epsilon,
                  "eps for dark pixels in image units (overrides --epsilon-fraction)");
  cmd->callback([options] { run_compare(*options); });
}

}  // namespace lb::app
