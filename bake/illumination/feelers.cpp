#include "bake/illumination/feelers.h"

#include <algorithm>
#include <numbers>

namespace lb {

vec2 disk_to_square(vec2 d) {
  const float r = glm::length(d);
  if (r == 0.0f) return vec2(0.5f);
  const float quarter_pi = std::numbers::pi_v<float> / 4.0f;
  float phi = std::atan2(d.y, d.x);
  if (phi < -quarter_pi) phi += 2.0f * std::numbers::pi_v<float>;  // phi in [-pi/4, 7pi/4)
  vec2 o;
  if (phi < quarter_pi) {
    o = {r, r * phi / quarter_pi};
  } else if (phi < 3.0f * quarter_pi) {
    o = {r * (2.0f * quarter_pi - phi) / quarter_pi, r};
  } else if (phi < 5.0f * quarter_pi) {
    o = {-r, -r * (phi - 4.0f * quarter_pi) / quarter_pi};
  } else {
    o = {-r * (6.0f * quarter_pi - phi) / quarter_pi, -r};
  }
  return glm::clamp(0.5f * (o + 1.0f), vec2(0.0f), vec2(1.0f));
}

namespace illumination {

namespace {

int zone_of(vec2 u, int zones_side) {
  const int x = std::clamp(int(u.x * float(zones_side)), 0, zones_side - 1);
  const int y = std::clamp(int(u.y * float(zones_side)), 0, zones_side - 1);
  return y * zones_side + x;
}

bool feeler_finds_specular(const Scene& scene, const Accel& accel, const Ray& ray) {
  const auto hit = accel.intersect(ray);
  return hit && is_specular(scene.materials[size_t(scene.meshes[hit->mesh].material)]);
}

// Marks the 8 neighbours of every marked zone (see the header on adjacency); with `wraps`
// the rows wrap around (a lamp's azimuth: the first and last rows touch).
std::vector<uint8_t> dilate_zones(const std::vector<uint8_t>& marked, int side, bool wraps) {
  std::vector<uint8_t> out(marked.size(), 0);
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x) {
      if (!marked[size_t(y * side + x)]) continue;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int nx = x + dx, ny = wraps ? (y + dy + side) % side : y + dy;
          if (nx >= 0 && ny >= 0 && nx < side && ny < side) out[size_t(ny * side + nx)] = 1;
        }
    }
  return out;
}

// Origins over a flat area light: a direction cell reaches a specular object from some points
// of the light only, and one feeler from a random point can miss it (that lost 2.4% of
// cornell_glass's caustic power against tracing every zone). Marks every cell with a
// direction passing within the light's radius of a bounding sphere from the centroid: a
// cone around the direction to the sphere's centre of half-angle asin((r + r_light) / d),
// widened by the cell's angular radius (from its corners). With the one-cell dilation after
// it, conservative: no ray from the light that hits the sphere leaves through an unmarked
// cell. A large bounding sphere (a plate's) marks far more than the object needs. Given only
// the spheres some aimed feeler reached: a sphere all of whose feelers end on something opaque
// before it (behind a wall) gets no cone; one seen only through a gap they all missed loses it.
void mark_cells_within_reach(const LightSetup& setup, const std::vector<Sphere>& spheres,
                             int fine_side, std::vector<uint8_t>& cells) {
  const auto direction = [&](float x, float y) {
    return setup.frame.to_world(square_to_cosine_hemisphere(vec2(x, y) / float(fine_side)));
  };
  for (const Sphere& sphere : spheres) {
    const vec3 to_centre = sphere.centre - setup.light->centroid;
    const float distance = glm::length(to_centre), reach = sphere.radius + setup.radius;
    const bool everywhere = distance <= reach;
    const vec3 axis = everywhere ? vec3(0.0f) : to_centre / distance;
    const float half_angle = everywhere ? 0.0f : std::asin(reach / distance);
    for (int y = 0; y < fine_side; ++y)
      for (int x = 0; x < fine_side; ++x) {
        uint8_t& cell = cells[size_t(y * fine_side + x)];
        if (cell) continue;
        if (everywhere) {
          cell = 1;
          continue;
        }
        const vec3 c = direction(float(x) + 0.5f, float(y) + 0.5f);
        float cell_radius = 0.0f;
        for (int k = 0; k < 4; ++k) {
          const vec3 corner = direction(float(x + (k & 1)), float(y + (k >> 1)));
          cell_radius =
              std::max(cell_radius, std::acos(std::clamp(glm::dot(c, corner), -1.0f, 1.0f)));
        }
        const float angle = std::acos(std::clamp(glm::dot(c, axis), -1.0f, 1.0f));
        if (angle <= half_angle + cell_radius) cell = 1;
      }
  }
}

}  // namespace

bool is_specular(const Material& material) {
  return !material.is_diffuse() && !material.is_emitter();
}

Sphere bounding_sphere(const Mesh& mesh) {
  Bounds b;
  for (vec3 p : mesh.positions) b.extend(p);
  Sphere s;
  s.centre = 0.5f * (b.min + b.max);
  for (vec3 p : mesh.positions) s.radius = std::max(s.radius, glm::length(p - s.centre));
  return s;
}

std::vector<uint8_t> find_traced_cells(const Scene& scene, const Accel& accel,
                                       const IlluminationParams& params, const ZoneGrid& grid,
                                       const LightSetup& setup,
                                       const std::vector<Sphere>& specular_spheres,
                                       uint64_t light_seed, uint64_t& casts) {
  const int side = grid.zones, fine_side = grid.fine();
  std::vector<uint8_t> zones(size_t(side * side), 0), cells(size_t(fine_side * fine_side), 0);
  auto mark = [&](vec2 u) {
    zones[size_t(zone_of(u, side))] = 1;
    cells[size_t(zone_of(u, fine_side))] = 1;
  };
  Rng rng(light_seed, 0xfee1);
  const int f = std::max(1, params.feelers_per_zone_side);
  for (int z = 0; z < side * side; ++z) {
    const int zx = z % side, zy = z / side;
    for (int k = 0; k < f * f; ++k) {
      const vec2 in_zone = stratified(k % f, k / f, f, f, rng.next_2d());
      const vec2 u = (vec2(float(zx), float(zy)) + in_zone) / float(side);
      const Ray ray = light_ray(scene, setup, u, rng.next_2d());
      ++casts;
      if (feeler_finds_specular(scene, accel, ray)) mark(u);
    }
  }
  const int a = std::max(0, params.aimed_feelers_side);
  // Area lights: the spheres some aimed feeler reached (or the light may sit inside): only
  // they get the cone below. A cone ignores walls: in a level of 100 rooms each light's cones
  // towards the other rooms' mirrors covered its hemisphere (3587 of 3600 zones traced).
  std::vector<Sphere> reached;
  for (const Sphere& sphere : specular_spheres) {
    if (setup.sources) {
      // Lamps and lights at infinity: a stratified grid over the sphere's disk as seen from
      // the lamp (or across the parallel rays), each found through the inverse of its map.
      const bool inside =
          !setup.zones_on_disk &&
          glm::length(sphere.centre - setup.sources->lamp(setup.source).position) <= sphere.radius;
      if (inside) continue;  // the grid feelers see it
      const vec3 axis =
          setup.zones_on_disk
              ? setup.direction
              : glm::normalize(sphere.centre - setup.sources->lamp(setup.source).position);
      const Frame towards(axis);
      for (int k = 0; k < a * a; ++k) {
        const vec2 d = square_to_disk(stratified(k % a, k / a, a, a, rng.next_2d()));
        const vec3 target =
            sphere.centre + sphere.radius * (d.x * towards.tangent + d.y * towards.bitangent);
        vec2 u;
        if (!square_towards(setup, target, u)) continue;
        const Ray ray = light_ray(scene, setup, u, rng.next_2d());
        ++casts;
        if (feeler_finds_specular(scene, accel, ray)) mark(u);
      }
      continue;
    }
    bool reaches =
        glm::length(sphere.centre - setup.light->centroid) <= sphere.radius + setup.radius;
    for (int k = 0; k < a * a; ++k) {
      vec3 position = setup.light->centroid, normal = setup.side * setup.light->normal;
      if (setup.over_light) {
        const LightSample s = setup.light->sample(scene, rng.next_2d());
        position = s.position, normal = setup.side * s.normal;
      }
      const vec3 to_centre = sphere.centre - position;
      if (glm::length(to_centre) <= sphere.radius) {  // the grid feelers see it
        reaches = true;
        continue;
      }
      const Frame towards(glm::normalize(to_centre));
      const vec2 d = square_to_disk(stratified(k % a, k / a, a, a, rng.next_2d()));
      const vec3 target =
          sphere.centre + sphere.radius * (d.x * towards.tangent + d.y * towards.bitangent);
      const vec3 direction = glm::normalize(target - position);
      const Frame frame(normal);
      const vec3 local = frame.to_local(direction);
      if (local.z <= 0.0f) continue;  // below the light's horizon: it emits nothing there
      Ray ray;
      ray.direction = direction;
      ray.origin = offset_ray_origin(position, normal, direction);
      ++casts;
      const auto hit = accel.intersect(ray);
      const bool specular =
          hit && is_specular(scene.materials[size_t(scene.meshes[hit->mesh].material)]);
      if (specular) mark(disk_to_square(vec2(local.x, local.y)));
      // Nothing opaque before the sphere: its object may be thin (a ring seen edge on) and
      // missed by these few feelers, but the cone below then covers it.
      const float along = glm::dot(sphere.centre - ray.origin, direction);
      const float off_axis = glm::length(sphere.centre - ray.origin - along * direction);
      const float entry =
          along - std::sqrt(std::max(0.0f, sphere.radius * sphere.radius - off_axis * off_axis));
      if (specular || !hit || hit->t >= 0.999f * entry) reaches = true;
    }
    if (reaches) reached.push_back(sphere);
  }
  if (a > 0 && setup.light && setup.over_light && setup.flat)  // aiming at the spheres, exactly
    mark_cells_within_reach(setup, reached, fine_side, cells);
  if (grid.sub > 1) {
    const std::vector<uint8_t> near = dilate_zones(zones, side, setup.wraps);
    for (int cell = 0; cell < fine_side * fine_side; ++cell) {
      if (!near[size_t(grid.zone_of_cell(cell))] || cells[size_t(cell)]) continue;
      const vec2 u = (vec2(float(cell % fine_side), float(cell / fine_side)) + rng.next_2d()) /
                     float(fine_side);
      const Ray ray = light_ray(scene, setup, u, rng.next_2d());
      ++casts;
      if (feeler_finds_specular(scene, accel, ray)) cells[size_t(cell)] = 1;
    }
  }
  return dilate_zones(cells, fine_side, setup.wraps);
}

}  // namespace illumination
}  // namespace lb
