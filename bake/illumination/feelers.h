#pragma once
// Feeler rays (Shirley 1990, section 3.1, Figure 2): per light, which sub-zones of the unit
// square - the light's cosine-weighted hemisphere through the concentric disk - see a specular
// surface and so get dense illumination rays. See illumination.h for the zones, the aimed
// feelers at small objects and the adjacency rule.

#include <cstdint>
#include <vector>

#include "bake/illumination/illumination.h"
#include "bake/illumination/light_rays.h"

namespace lb::illumination {

// Specular surfaces redirect light (mirror, glass, glossy) and are what feelers look for.
bool is_specular(const Material& material);

struct Sphere {
  vec3 centre{0.0f};
  float radius = 0.0f;
};
Sphere bounding_sphere(const Mesh& mesh);

// The two partitions of the unit square: feeler_zones^2 zones, each cut into
// subzones_side^2 sub-zones; `fine` is the side of the sub-zone grid.
struct ZoneGrid {
  int zones = 6;
  int sub = 1;
  int rays_side = 1;  // dense rays per sub-zone side
  int fine() const { return zones * sub; }
  int zone_of_cell(int cell) const {
    const int f = fine();
    return (cell / f / sub) * zones + (cell % f) / sub;
  }
};

// Feelers of one light: grid feelers per zone, aimed feelers at each specular mesh's
// bounding sphere (for a flat light with origins over its area: every sub-zone whose cone
// reaches the sphere from some point of the light, found geometrically), then one feeler per
// sub-zone of the zones found (and their neighbours).
// Returns the sub-zones to trace (marks dilated to their 8 neighbours); adds the rays cast.
std::vector<uint8_t> find_traced_cells(const Scene& scene, const Accel& accel,
                                       const IlluminationParams& params, const ZoneGrid& grid,
                                       const LightSetup& setup,
                                       const std::vector<Sphere>& specular_spheres,
                                       uint64_t light_seed, uint64_t& casts);

}  // namespace lb::illumination
