#pragma once
// A false-colour picture of a per-pixel error image (from relative_error_image), for looking at
// where a bake is wrong: 0 is black, then blue, magenta, orange, to pale yellow at `max_error`
// and above (a monotone ramp in lightness, readable in grey print). Pixels marked not compared
// (negative) are mid grey.

#include <array>

#include "bake/io/image_io.h"

namespace lb {

// Linear display RGB in [0, 1] for one error value; `max_error` > 0.
std::array<float, 3> false_colour(double error, double max_error);

// The whole image as linear display RGB (write with write_png).
Image false_colour_image(const Image& error, double max_error);

}  // namespace lb
