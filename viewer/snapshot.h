#pragma once
// Offscreen rendering of one view (the `lightbake snapshot` command and the image tests).

#include <string>

#include "bake/bake_result.h"
#include "bake/io/image_io.h"
#include "viewer/render_settings.h"
#include "viewer/shader_program.h"
#include "viewer/shadow_resolution.h"
#include "viewer/view_camera.h"

namespace lb {

struct SnapshotOptions {
  std::string camera;  // a scene camera's name or index; empty: the first, else fit-to-scene
  int width = 640;
  int height = 480;
  RenderSettings settings;  // direct_mode full by default: exact bits in one frame
  // Frames averaged with DirectMode::stochastic (their running mean is the image; the
  // full mode is the exact one, docs/viewer.md).
  int frames = 64;
  // N: each pixel is the mean of N x N frames sampled at the centres of an N x N grid of
  // sub-pixels (a box filter over the pixel, as the reference and HQ mode integrate it); 1:
  // one sample at the pixel's centre. Each frame also has its own interleaved set of shadow
  // points (ShadowSettings::interleave). Ignored with DirectMode::stochastic (pixel centres).
  int pixel_samples = 1;
  ShadowSettings shadows;
  std::string shader_directory = default_shader_directory();
};

// The camera `name_or_index` of the scene; throws std::invalid_argument naming the choices.
ViewCamera choose_camera(const Scene& scene, const std::string& name_or_index);

// The largest difference of tone-mapped display values (linear [0,1] after exposure and curve,
// then sRGB-encoded, before rounding to 8 bits) over all pixels and channels of two images of
// one size: 1/255 is one step of an 8-bit display.
double max_display_difference(const Image& a, const Image& b, const ToneMap& tone);

// Linear radiance (RGB, top row first) rendered with OSMesa on the calling thread; with
// `shadows`, the shadow maps' size it used and why.
Image render_snapshot(const Scene& scene, const BakeResult* bake, const SnapshotOptions& options,
                      ShadowResolution* shadows = nullptr);

}  // namespace lb
