#include "bake/export/export_settings.h"

#include <stdexcept>

#include "bake/io/ktx2_encode.h"
#include "bake/lightmap/oidn.h"

namespace lb {

GltfExportOptions resolve_export_settings(const ExportSettings& settings) {
  if (settings.directional_share && !settings.directional)
    throw std::invalid_argument(
        "--directional-share: give --directional too (s is the directional maps')");
  if (settings.shadow_side > 0 && (settings.contents != "all" || settings.directional))
    throw std::invalid_argument(
        "--shadow-rays: only the direct term of --contents all without --directional");
  GltfExportOptions gltf;
  gltf.contents = parse_lightmap_contents(settings.contents);
  gltf.format = parse_lightmap_format(settings.format);
  gltf.encoding = parse_lightmap_encoding(settings.encoding);
  gltf.direct_side = settings.direct_side;
  gltf.shadow_side = settings.shadow_side;
  gltf.directional = settings.directional;
  gltf.directional_share = settings.directional_share;
  gltf.stitch_seams = !settings.no_seam_stitching;
  try {
    if (settings.denoise) {
      if (gltf.contents != LightmapContents::all)
        throw std::invalid_argument(
            "--denoise: only the direct term of --contents all is denoised");
      require_oidn();  // before any bake: a missing library is refused in a second
      gltf.denoise_direct = true;
    }
    if (settings.ktx2) gltf.ktx2_encoder = find_basisu();
  } catch (const std::runtime_error& e) {
    throw std::invalid_argument(e.what());
  }
  return gltf;
}

}  // namespace lb
