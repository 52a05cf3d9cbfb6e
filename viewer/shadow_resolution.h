#pragma once
// The shadow maps' size for a scene (ShadowSettings::resolution = 0, the default).
//
// A caster thinner than about a shadow-map texel loses its shadow where it stands on a
// floor: the depth bias that keeps a grazing floor from shadowing itself (shadow_maps.cpp's
// slope offset, shaders/shadows.glsl's receiver lift) spans about a texel of depth, so at the
// caster's foot the floor on its far side compares against the floor on the light's side and
// comes out lit. Figure 3's napkin ring (a 4 mm wall 1.47 m from its lamp) showed a lit line
// along its foot at 512 texels (5.7 mm at the ring), which its mirror walls spread into bands:
// the raster image 0.0374 MRE off the reference, 0.0286 at 768 texels, 0.0253 at 1024 (lines
// gone), where the other bundled scenes gain nothing (docs/viewer.md, "Shadows"). So the size
// follows the thinnest closed caster, its thickness 2 V / A (exact for a slab or shell, a
// third of a cube's edge), against the distance from each light to its centre: a texel there
// no wider than kTexelPerThickness of its thickness (the ring: 3.8 mm = 1.03 t at 768 texels
// left part of the lines, 2.9 mm = 0.77 t at 1024 none), in steps of 256 texels, never below
// kMinShadowResolution (the fixed size before, so scenes without thin casters keep their
// images) and within kShadowMemoryBudget.

#include <string>

#include "bake/lights.h"
#include "bake/scene.h"

namespace lb {

constexpr int kMinShadowResolution = 512;
constexpr double kShadowMemoryBudget = 512.0 * 1024 * 1024;  // bytes of 32-bit depth
constexpr float kTexelPerThickness = 0.8f;

// Twice the enclosed volume over the area of a closed mesh (every edge shared by exactly two
// triangles, vertices welded by position): its thickness for a slab or a shell. Infinity for
// an open mesh (a quad, a plane), whose depth has no back to lose.
float closed_mesh_thickness(const Mesh& mesh);

struct ShadowResolution {
  int resolution = kMinShadowResolution;  // texels per face edge
  std::string caster;       // the mesh that set it above the minimum, empty if none
  float thickness = 0.0f;   // m, of that mesh
  float distance = 0.0f;    // m, from the light that needs the finest texel
  bool capped = false;      // the memory budget held it below what the caster needs
};

// The size for `scene` with `layers` depth layers in all (6 per shadow cube or point lamp).
ShadowResolution automatic_shadow_resolution(const Scene& scene,
                                             const std::vector<AreaLight>& lights, int layers);

}  // namespace lb
