#include "app/export_options.h"

namespace lb::app {

void add_export_options(CLI::App& cmd, ExportSettings& settings, bool with_directional) {
  cmd.add_option("--contents", settings.contents,
                 "Lightmap contents: indirect (caustics + soft light; the engine draws the "
                 "direct light) or all (+ direct light with soft shadows)")
      ->capture_default_str();
  cmd.add_option("--lightmap-format", settings.format,
                 "Radiance file(s) beside the glTF: exr (half float), hdr (Radiance), both")
      ->capture_default_str();
  cmd.add_option("--lightmap-encoding", settings.encoding,
                 "The 8-bit map in the glTF: srgb (scaled sRGB, decoded by any engine's "
                 "sampler) or rgbm (RGB x alpha x scale, decoded in the shader: 8 bits of "
                 "precision at every brightness; docs/export.md)")
      ->capture_default_str();
  // N x N rays: up to 64 a side.
  const auto add_side = [&cmd](const char* name, int& side, const char* help) {
    cmd.add_option(name, side, help)->capture_default_str()->check(CLI::Range(0, 64));
  };
  add_side("--direct-samples", settings.direct_side,
           "--contents all: N x N shadow rays per lightmap cell (4N^2 per texel); 0: "
           "automatic, 4 to 16, more where texels are few");
  add_side("--shadow-rays", settings.shadow_side,
           "--contents all: N x N shadow rays a cell on average, spent where the shadows are; "
           "every --direct-samples point places the texels' fit (pair with --denoise); 0: a "
           "ray from every point");
  cmd.add_flag("--denoise", settings.denoise,
               "--contents all: the direct term's shadows through Intel Open Image Denoise "
               "(its library: $LIGHTBAKE_OIDN_LIB, pip package pyoidn; docs/export.md)");
  cmd.add_flag("--no-seam-stitching", settings.no_seam_stitching,
               "Leave chart seams as baked (off only to measure what stitching fixes)");
  cmd.add_flag("--ktx2", settings.ktx2,
               "Also store the 8-bit map as KTX2 with its mip chain (Basis UASTC, RGBM with one "
               "multiplier per 4x4 block; KHR_texture_basisu, the PNG as fallback; the maps "
               "grow to sides in multiples of 4) for web engines; needs basisu "
               "($LIGHTBAKE_BASISU or PATH; docs/export.md)");
  if (!with_directional) return;
  cmd.add_flag("--directional", settings.directional,
               "Directional lightmap: the map's L1 band (light's direction per texel, so "
               "normal and bump maps shade under baked light) as 3 more textures "
               "(LIGHTBAKE_lightmap_directional, docs/export.md); with the bake's caustic and "
               "soft-light bands where it has them (bake --directional; baking first, it bakes "
               "them), else the soft light's gathered here; 4x the plain map's bytes");
  cmd.add_flag("--directional-share", settings.directional_share,
               "With --directional: the x map as RGBA holding s, the direct term's share of "
               "L0, in its alpha (13/3 of the plain map's bytes instead of 4x; bumped "
               "surfaces under direct light closer to the reference, docs/export.md)");
}

}  // namespace lb::app
