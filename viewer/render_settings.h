#pragma once
// What a frame shows: the terms of L = R * (direct + illumination map + vertex radiosity),
// the paper's Figure 8 toggles, the debug outputs and the tone mapping. One struct, bound to
// the snapshot CLI and the ImGui panel alike.

#include <string>
#include <vector>

#include "bake/io/image_io.h"
#include "bake/scene.h"

namespace lb {

// Debug output. Numbers match shaders/common.glsl. The light terms are shown multiplied by
// the reflectance, i.e. as the radiance they contribute to the final image.
enum class Term {
  all = 0,        // emission + R * (direct + caustic + radiosity + ambient), specular: env
  direct,         // R * direct light from the area lights, with shadows and bump
  caustic,        // R * illumination map (L S+ D)
  radiosity,      // R * vertex radiosity (two or more diffuse bounces)
  ambient,        // R * the constant ambient term
  specular,       // mirrors, glass and glossy metal from the environment capture
  normals,        // bumped shading normal, 0.5 n + 0.5
  texel_density,  // checker: one square per illumination-map texel
  patches,        // radiosity patch ids as colours
  reflectance,    // R alone
  baked,          // emission + R * (caustic + radiosity): everything baked, no dynamic light,
                  // specular surfaces black (no environment); what an engine shows from the
                  // exported file with no lights of its own (docs/export.md, tests/web/)
};
const char* to_string(Term term);
Term parse_term(const std::string& name);  // throws std::invalid_argument listing the names
std::vector<std::string> term_names();

// How the direct light's shadows are evaluated (shaders/light_pick.glsl).
enum class DirectMode {
  full,        // every light's shadow lookups in every frame: exact in one frame
  stochastic,  // one light's per fragment, picked by its unshadowed contribution; frames of a
               // still camera accumulate to the full image (Renderer::accumulated_frames)
};
const char* to_string(DirectMode mode);
DirectMode parse_direct_mode(const std::string& name);  // throws std::invalid_argument

struct RenderSettings {
  Term term = Term::all;
  bool direct = true;   // per-fragment direct light
  bool shadows = true;  // off: the unoccluded direct light
  DirectMode direct_mode = DirectMode::full;
  // Stochastic mode, still camera: after the first frame, the full evaluation in this many
  // horizontal bands, one per frame, replaces the estimate, so the image is exact after
  // refine_bands + 1 frames and costs nothing more. 0: the frames' running mean, forever.
  int refine_bands = 4;
  bool caustics = true;         // illumination map
  bool radiosity = true;        // vertex radiosity
  // The maps' L1 bands (a directional export's; a directional bake's caustic and soft maps,
  // bake/sh_projection.h) evaluated with the shading normal, bump or normal map included; off:
  // the maps as they are (L0).
  bool directional = false;
  bool ambient = false;         // Whitted's constant ambient term (Figure 8, top middle)
  vec3 ambient_radiance{0.1f};  // E/pi of the ambient term, W/(sr m^2)
  ToneMap tone;                 // exposure (stops) and curve, as bake/io/image_io.h
  // Planar mirrors' own passes (Renderer, at most kMaxPlanarPasses). Off, every mirror reads
  // the environment capture: a level of detail the window takes while the camera moves.
  bool planar_reflections = true;
  // Levels of detail (viewer/mesh_detail.h): the geometric error a camera pass may show, in
  // pixels of its image; 0 draws every mesh at full detail. The window takes 1 while the
  // camera moves; still frames and snapshots keep full detail unless asked.
  float detail_pixels = 0.0f;
  // Bump maps read at full resolution (shaders/bump.glsl): each frame aliases where bumps are
  // minified, and the mean of several frames is the bumped shading; otherwise one mip level
  // finer than the pixel's, smooth but too bright there. render_snapshot's still images of
  // N x N sub-pixel frames (N >= 2) set it.
  bool bump_full_resolution = false;
};

// Figure 8's lighting presets on one scene: 0 direct only, 1 direct + constant ambient
// (Whitted), 2 direct + radiosity, 3 direct + radiosity + caustic maps. (The figure's other
// two panels are scene variants: a smaller light, a diffuse block in place of the ball.)
RenderSettings figure8_preset(int index, RenderSettings base = {});
constexpr int kFigure8PresetCount = 4;
const char* figure8_preset_name(int index);

// How the soft shadows are made (shaders/shadows.glsl): K depth cubes per light.
struct ShadowSettings {
  // Texels per cube face edge, memory growing squared; 0 = automatic, 512 or more as the
  // thinnest caster needs (viewer/shadow_resolution.h).
  int resolution = 0;
  // K; 0 = automatic: max(2, min(16, total_samples / lights)), and fewer (down to 1) where
  // 6 K lights faces would pass the depth array's layer limit (viewer/shadow_maps.h).
  int samples_per_light = 0;
  int total_samples = 24;     // budget for the automatic K; per-fragment cost is K lookups
  uint64_t seed = 1;          // jitter of the points on the lights
  // Still images of several frames (render_snapshot's sub-pixel samples): frame `set` of
  // `interleave` x `interleave` frames takes every interleave-th cell of a grid interleave
  // times finer in each direction, so each frame's K points are stratified over the light
  // and all frames' together are K * interleave^2 points stratified more finely.
  int interleave = 1;
  int set = 0;
};

}  // namespace lb
