#pragma once
// What a user asks of an export, in the words of `lightbake export`'s options: the command
// line and the viewer's Export panel fill this one struct and resolve it here, so the two
// check and mean the same (docs/export.md; the options' help: app/export_options.cpp).

#include <string>

#include "bake/export/gltf_export.h"

namespace lb {

struct ExportSettings {
  std::string contents = "indirect";  // indirect | all (+ the direct light)
  std::string format = "exr";         // radiance files beside: exr | hdr | both
  std::string encoding = "srgb";      // the 8-bit map inside: srgb | rgbm
  bool denoise = false;               // the direct term through Open Image Denoise (all)
  bool ktx2 = false;                  // the map also as KTX2 (needs basisu)
  bool directional = false;           // the map's L1 band as 3 more textures
  bool directional_share = false;     // s in the x map's alpha (needs directional)
  bool no_seam_stitching = false;     // seams as baked (to measure what stitching fixes)
  int direct_side = 0;                // --direct-samples (contents all; 0: automatic)
  int shadow_side = 0;                // --shadow-rays (contents all; 0: a ray a point)
};

// The export's options for `settings`, every check made before any bake: throws
// std::invalid_argument with one line naming the option and why (a contradiction, an unknown
// word, Open Image Denoise or basisu missing: then how to get it).
GltfExportOptions resolve_export_settings(const ExportSettings& settings);

}  // namespace lb
