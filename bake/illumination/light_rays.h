#pragma once
// Rays leaving a light for pass 1. The feeler zones live in the unit square, mapped by
// measure (so equal areas carry equal power up to a lamp's falloff):
//   area lights: through the concentric disk onto the cosine-weighted hemisphere, from the
//     light's centre or from stratified points over it;
//   point and spot lamps: LightSources::emit's uniform map onto the sphere / the outer cone
//     (x: cos of the angle to the axis, y: azimuth, periodic), the spot's falloff in each
//     ray's weight;
//   directional lamps and each direction of the sky: parallel rays from the disk that covers
//     the scene, the square mapped onto the disk by the concentric map (the direction fixed).

#include <vector>

#include "bake/accel.h"
#include "bake/light_sources.h"
#include "bake/lights.h"
#include "bake/sampling.h"

namespace lb::illumination {

struct Sphere;  // feelers.h (which includes this header)

// Where a light's rays start and which frame their directions live in.
struct LightSetup {
  const AreaLight* light = nullptr;  // area lights; nullptr for lamps and sky directions
  // The side rays leave from: 1 the front, -1 the back. A two-sided light is two setups, one
  // per side, each with half its power.
  float side = 1.0f;
  bool over_light = false;
  bool flat = true;     // every direction lives in `frame` (the light's normal is one vector)
  float radius = 0.0f;  // farthest vertex from the centroid, metres
  Frame frame{vec3(0, 0, 1)};
  // Rays from the centre all leave on the light's front side, so they share one origin.
  vec3 centre_origin{0.0f};
  // Lamps and the sky: LightSources::emit(source, ...).
  const LightSources* sources = nullptr;
  size_t source = 0;
  // Directional lamps and sky directions: the zones cover the disk; u_direction stays fixed.
  bool zones_on_disk = false;
  vec2 fixed_u_direction{0.5f};
  vec3 direction{0.0f};  // their rays' direction
  bool wraps = false;    // point and spot: the square's y (azimuth) is periodic
  // Power sent through all the zones, W per channel, and the max channel of a ray's emitted
  // power that weighs 1 (a spot's rays weigh their falloff; every other ray 1).
  vec3 power{0.0f};
  float unit_power = 1.0f;
  int rays_side = 0;  // dense rays per sub-zone side; 0: the pass's own (the sky uses fewer)
  int group = -1;     // the light's group (bake/light_groups.h); -1: the scene has none
};

// Automatic ray origins (CausticOrigins::automatic) leave from all over a light whose radius
// seen from the nearest specular object (radius / distance to its bounding sphere) exceeds
// this, in radians; from its centre otherwise (the paper's choice, for less noise). 0.05 rad
// (~3 degrees): the caustic's soft fringe is then ~5% of the specular object's size or less.
// The room's 0.8 m light, 2.2 m above the glass ball, is at 0.26: from its centre the caustic
// region was 3.6% off the reference, over its area 3.2% (sum ratio 0.987 -> 0.999;
// docs/illumination.md).
inline constexpr float kCentreOriginMaxAngle = 0.05f;

// Origins over the whole light or at its centre, as the light's mesh asks
// (MeshBakeSettings::caustic_origins); automatic: over the light when its angle to the nearest
// of `specular` (bounding spheres) exceeds kCentreOriginMaxAngle. A light that is not flat
// always gets origins over it.
LightSetup setup_light(const Scene& scene, const AreaLight& light,
                       const std::vector<Sphere>& specular);
// The back of a two-sided light's front setup: the frame and origins mirrored, half the
// power in each.
LightSetup split_off_back(LightSetup& front);

// The farthest vertex of an area light from its centroid, metres.
float light_radius(const Scene& scene, const AreaLight& light);

// The light's radius (farthest vertex from its centroid) over its distance to the nearest
// bounding sphere's surface; infinity when the light reaches into one, 0 with none.
float light_angle_to_specular(const Scene& scene, const AreaLight& light,
                              const std::vector<Sphere>& specular);

// A point, spot or directional lamp of `sources` (all its power).
LightSetup setup_lamp(const LightSources& sources, size_t light);
// One direction of the sky `light`: u_direction picks it (SkyLight::sample through
// LightSources::emit), and it carries 1/`directions` of what the sky sends that way over its
// density, so the mean over uniform u_direction of `directions` such setups is the sky's power.
LightSetup setup_sky_direction(const LightSources& sources, size_t light, vec2 u_direction,
                               int directions);

// A ray leaving the light: `u_zone` in the unit square (zones live there), `u_other` picks
// the point on an area light when origins are spread over it (unused by lamps and the sky).
// Returns the ray's weight: its power is weight * setup.power / rays (a spot's falloff; 1
// otherwise). Written in place: a returned Ray copied into an array stalls on store forwarding.
float light_ray(const Scene& scene, const LightSetup& setup, vec2 u_zone, vec2 u_other, Ray& ray);
Ray light_ray(const Scene& scene, const LightSetup& setup, vec2 u_zone, vec2 u_other);

// The point of the unit square whose lamp or disk ray passes through `target` (aimed feelers
// of lamps and lights at infinity); false when no ray of the setup does (outside a spot's
// cone, off the disk, or at the lamp itself). Not for area lights.
bool square_towards(const LightSetup& setup, vec3 target, vec2& u);

}  // namespace lb::illumination
