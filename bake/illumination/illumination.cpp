#include "bake/illumination/illumination.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>

#include "bake/bsdf.h"
#include "bake/bump.h"
#include "bake/illumination/atlas.h"
#include "bake/illumination/density_filter.h"
#include "bake/illumination/feelers.h"
#include "bake/illumination/light_rays.h"
#include "bake/illumination/splat.h"
#include "bake/light_groups.h"
#include "bake/light_sources.h"
#include "bake/sampling.h"
#include "bake/sh_projection.h"

namespace lb {

namespace {

using namespace illumination;

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// One block's tallies, summed in its own fixed order, then rounded once into the pass's
// fixed-point tallies (fixed_sums.h).
struct Tally {
  glm::dvec3 sent{0.0}, deposited{0.0}, absorbed{0.0}, escaped{0.0}, direct{0.0}, unmapped{0.0};
  uint64_t casts = 0, rays = 0, emitter_hits = 0;
  FixedTally to_fixed(const FixedScale& scale) const {
    FixedTally t;
    for (int c = 0; c < 3; ++c) {
      const double unit = scale.power_unit[c];
      t.sent[c] = illumination::to_fixed(sent[c], unit, "power sent");
      t.deposited[c] = illumination::to_fixed(deposited[c], unit, "power deposited");
      t.absorbed[c] = illumination::to_fixed(absorbed[c], unit, "power absorbed");
      t.escaped[c] = illumination::to_fixed(escaped[c], unit, "power escaped");
      t.direct[c] = illumination::to_fixed(direct[c], unit, "direct power");
      t.unmapped[c] = illumination::to_fixed(unmapped[c], unit, "unmapped power");
    }
    t.casts = casts, t.rays = rays, t.emitter_hits = emitter_hits;
    return t;
  }
};

// Where deposits go: the atlas's nodes in the pass's fixed-point sums, as paths arrive.
struct SplatTarget {
  const Atlas& atlas;
  const FixedScale& scale;
  Pass1Sums& sums;
  bool pilot = false;  // keep each deposit's place in BlockResult::deposits instead
};

// A pilot deposit: the diffuse mesh and the point the light reached.
struct PilotDeposit {
  uint32_t mesh = 0;
  vec3 position{0.0f};
};

struct BlockResult {
  Tally tally;
  std::vector<Ray> casts;              // only with params.cast_log
  std::vector<PilotDeposit> deposits;  // only for the pilot
};

// Where a specular hit scatters from: only what scattering needs (surface_at would also
// interpolate texture coordinates and tangents).
struct SpecularPoint {
  vec3 position{0.0f};
  vec3 shading_normal{0.0f};
};

SpecularPoint specular_point(const Scene& scene, const Hit& hit) {
  const Mesh& mesh = scene.meshes[hit.mesh];
  const uvec3 tri = mesh.triangles[hit.triangle];
  const float b0 = 1.0f - hit.barycentric.x - hit.barycentric.y;
  const float b1 = hit.barycentric.x, b2 = hit.barycentric.y;
  SpecularPoint p;
  // Interpolating the vertices is more precise than origin + t * direction far from the origin.
  p.position = b0 * mesh.positions[tri.x] + b1 * mesh.positions[tri.y] + b2 * mesh.positions[tri.z];
  p.shading_normal = hit.geometric_normal;
  if (!mesh.normals.empty()) {
    const vec3 n = b0 * mesh.normals[tri.x] + b1 * mesh.normals[tri.y] + b2 * mesh.normals[tri.z];
    const float length = glm::length(n);
    if (length > 0.0f) p.shading_normal = n / length;
  }
  return p;
}

// A deposit's L1 band (sh_projection.h) about the unbumped shading normal at the hit, n0, the
// normal every renderer decodes the band with: power P (d - n0 cos) / cos, d the direction
// the light came from, cos = d . n0. Light more grazing than cos = 1e-3 (0.06 degrees off the
// plane) adds no L1 (its 1/cos weight is unbounded; de-ringing caps what such light could
// bring at L0 anyway), and so does light from behind n0 (a shading normal that disagrees with
// the triangle's side).
std::array<vec3, 3> deposit_l1(const Scene& scene, const Hit& hit, const Ray& ray, vec3 power) {
  const vec3 from = -glm::normalize(ray.direction);
  const vec3 n0 = specular_point(scene, hit).shading_normal;
  if (!(glm::dot(from, n0) > 1e-3f)) return {vec3(0.0f), vec3(0.0f), vec3(0.0f)};
  return l1_of_sample(power, from, n0);
}

// Paths traced together: up to this many primaries of one block, then their survivors.
constexpr size_t path_chunk = 256;

// Follows `count` illumination rays (carrying `ray_power` times their `weights`) through
// specular bounces until each is absorbed, escapes, or reaches a diffuse surface (deposited
// if it met a specular surface before, else dropped). The paths advance one bounce at a time
// so Embree gets each wave of rays at once: a sub-zone's primaries are coherent and are traced
// as packets. A lamp with a range fades by its window at the first hit (faded: absorbed).
// `rays` is overwritten with the waves.
void trace_paths(const Scene& scene, const Accel& accel, const IlluminationParams& params,
                 const LightSetup& setup, Ray* rays, const float* weights, size_t count,
                 vec3 ray_power, Rng& rng, const SplatTarget& target, BlockResult& out) {
  Tally& tally = out.tally;
  std::array<std::optional<Hit>, path_chunk> hits;
  std::array<vec3, path_chunk> powers;
  for (size_t k = 0; k < count; ++k) {
    powers[k] = ray_power * weights[k];
    tally.sent += glm::dvec3(powers[k]);
  }
  size_t live = count;
  for (int bounces = 0; live > 0; ++bounces) {
    if (params.cast_log) out.casts.insert(out.casts.end(), rays, rays + live);
    accel.intersect_many(rays, live, hits.data(), true);
    tally.casts += live;
    size_t survivors = 0;
    for (size_t k = 0; k < live; ++k) {
      vec3 power = powers[k];
      if (bounces == 0 && setup.sources) {
        const float distance = hits[k] ? hits[k]->t : std::numeric_limits<float>::infinity();
        const vec3 kept = power * setup.sources->range_window(setup.source, distance);
        tally.absorbed += glm::dvec3(power) - glm::dvec3(kept);
        power = kept;
      }
      const std::optional<Hit>& hit = hits[k];
      if (!hit) {
        tally.escaped += glm::dvec3(power);
        continue;
      }
      const Material& material = scene.materials[size_t(scene.meshes[hit->mesh].material)];
      if (material.is_emitter()) {
        tally.absorbed += glm::dvec3(power);
        ++tally.emitter_hits;
        continue;
      }
      if (material.is_diffuse()) {
        const bool front = glm::dot(rays[k].direction, hit->geometric_normal) < 0.0f;
        if (bounces == 0) {
          tally.direct += glm::dvec3(power);
        } else if (front) {
          tally.deposited += glm::dvec3(power);
          std::optional<std::array<vec3, 3>> l1;
          if (params.directional && !target.pilot) l1 = deposit_l1(scene, *hit, rays[k], power);
          if (target.pilot)
            out.deposits.push_back({hit->mesh, rays[k].origin + hit->t * rays[k].direction});
          else if (!splat_deposit(target.atlas, scene, target.scale, hit->mesh, hit->triangle,
                                  hit->barycentric, power, target.sums, setup.group,
                                  l1 ? &*l1 : nullptr))
            tally.unmapped += glm::dvec3(power);
        } else {
          tally.absorbed += glm::dvec3(power);  // the back of a one-sided diffuse surface
        }
        continue;
      }
      if (bounces >= params.max_depth) {
        tally.absorbed += glm::dvec3(power);
        continue;
      }
      const SpecularPoint sp = specular_point(scene, *hit);
      const vec3 incident = glm::normalize(rays[k].direction);
      // specular_normal (bump.h), the step every ray tracer takes; without a bump map the same
      // rule on the interpolated normal, without building the whole surface point: shading
      // normals give smooth caustics from tessellated balls, the geometric normal takes over
      // where the two disagree about which side the ray comes from.
      vec3 normal;
      if (material.bump != BumpKind::none) {
        normal = specular_normal(scene, surface_at(scene, *hit, rays[k]), incident);
      } else {
        const bool agree = (glm::dot(incident, sp.shading_normal) < 0.0f) ==
                           (glm::dot(incident, hit->geometric_normal) < 0.0f);
        normal = agree ? sp.shading_normal : hit->geometric_normal;
      }
      const auto scatter = scatter_specular(material, incident, normal, rng.next_2d());
      if (!scatter) {
        tally.absorbed += glm::dvec3(power);
        continue;
      }
      vec3 next = power * scatter->weight;
      if (bounces + 1 >= params.roulette_depth) {
        const vec3 throughput = next / glm::max(ray_power, vec3(1e-30f));
        const float survive = std::min(1.0f, std::max({throughput.x, throughput.y, throughput.z}));
        if (!(survive > 0.0f) || rng.next_float() >= survive) {
          tally.absorbed += glm::dvec3(power);
          continue;
        }
        next /= survive;
      }
      tally.absorbed += glm::dvec3(power) - glm::dvec3(next);  // may be < 0 after roulette
      Ray& ray = rays[survivors];  // survivors <= k: the wave compacts in place
      ray.origin = offset_ray_origin(sp.position, hit->geometric_normal, scatter->direction);
      ray.direction = scatter->direction;
      ray.tmin = 0.0f;
      ray.tmax = 1e30f;
      powers[survivors] = next;
      ++survivors;
    }
    live = survivors;
  }
}

struct WorkItem {
  int light = 0;
  int cell = 0;  // sub-zone index in the fine grid
  int first_row = 0;
  int rows = 0;
};

// Dense rays of one block: rows [first_row, first_row + rows) of the sub-zone's ray grid.
BlockResult trace_block(const Scene& scene, const Accel& accel, const IlluminationParams& params,
                        const ZoneGrid& grid, const LightSetup& setup, const WorkItem& item,
                        const SplatTarget& target) {
  const int m = setup.rays_side > 0 ? setup.rays_side : grid.rays_side, fine_side = grid.fine();
  const int cx = item.cell % fine_side, cy = item.cell / fine_side;
  // Each sub-zone carries 1/fine^2 of the power: the maps preserve the measure (a spot's rays
  // carry their falloff in their weight).
  const vec3 ray_power = setup.power / float(fine_side * fine_side) / (float(m) * float(m));
  // Origins over the light: a shuffled pairing of direction strata with origin strata, the
  // same for every block of the sub-zone.
  std::vector<uint32_t> origin_stratum;
  if (setup.over_light && params.stratified) {
    origin_stratum.resize(size_t(m) * size_t(m));
    for (size_t k = 0; k < origin_stratum.size(); ++k) origin_stratum[k] = uint32_t(k);
    Rng shuffle(hash_seed(params.seed, uint64_t(item.light), uint64_t(item.cell)), 0x5eed);
    for (size_t k = origin_stratum.size() - 1; k > 0; --k)
      std::swap(origin_stratum[k], origin_stratum[shuffle.next_u32() % (k + 1)]);
  }
  Rng rng(hash_seed(params.seed, uint64_t(item.light),
                    (uint64_t(item.cell) << 32) | uint64_t(item.first_row)));
  BlockResult result;
  std::array<Ray, path_chunk> rays;
  std::array<float, path_chunk> weights;
  size_t n = 0;
  // Rays go in 4 x 4 tiles of the sub-zone's grid: Embree's packets take consecutive rays, and
  // a square tile keeps each packet's directions closest together.
  const int end_row = item.first_row + item.rows;
  for (int tile_j = item.first_row; tile_j < end_row; tile_j += 4)
    for (int tile_i = 0; tile_i < m; tile_i += 4)
      for (int j = tile_j; j < std::min(tile_j + 4, end_row); ++j)
        for (int i = tile_i; i < std::min(tile_i + 4, m); ++i) {
          const vec2 in_cell =
              params.stratified ? stratified(i, j, m, m, rng.next_2d()) : rng.next_2d();
          const vec2 u = (vec2(float(cx), float(cy)) + in_cell) / float(fine_side);
          vec2 u_origin = rng.next_2d();
          if (!origin_stratum.empty()) {
            const uint32_t s = origin_stratum[size_t(j) * size_t(m) + size_t(i)];
            u_origin = stratified(int(s % uint32_t(m)), int(s / uint32_t(m)), m, m, u_origin);
          }
          weights[n] = light_ray(scene, setup, u, u_origin, rays[n]);
          if (++n == path_chunk) {
            trace_paths(scene, accel, params, setup, rays.data(), weights.data(), n, ray_power, rng,
                        target, result);
            n = 0;
          }
        }
  if (n > 0)
    trace_paths(scene, accel, params, setup, rays.data(), weights.data(), n, ray_power, rng, target,
                result);
  result.tally.rays += uint64_t(item.rows) * uint64_t(m);
  return result;
}

// Serialises progress reports from worker threads.
class ProgressCounter {
 public:
  ProgressCounter(const Progress& progress, std::string_view stage, size_t total)
      : progress_(progress), stage_(stage), total_(std::max<size_t>(1, total)) {}
  void step() {
    const size_t done = ++done_;
    std::lock_guard lock(mutex_);
    progress_.update(stage_, double(done) / double(total_));
  }

 private:
  const Progress& progress_;
  std::string_view stage_;
  size_t total_;
  std::atomic<size_t> done_{0};
  std::mutex mutex_;
};

}  // namespace

int64_t rays_saved_by_feelers(const IlluminationStats& stats, const IlluminationParams& params) {
  const int sub = std::max(1, params.subzones_side);
  const int64_t side = int64_t((std::max(1, params.rays_per_zone_side) + sub - 1) / sub) * sub;
  return int64_t(stats.zones_total) * side * side - int64_t(stats.illumination_rays) -
         int64_t(stats.feeler_rays);
}

void check_illumination_params(const IlluminationParams& params) {
  auto check = [](const char* name, int value, int lo, int hi) {
    if (value < lo || value > hi)
      throw std::invalid_argument("illumination: " + std::string(name) + " = " +
                                  std::to_string(value) + " is outside [" + std::to_string(lo) +
                                  ", " + std::to_string(hi) + "]");
  };
  check("feeler_zones", params.feeler_zones, 1, kMaxFeelerGridSide);
  check("subzones_side", params.subzones_side, 1, kMaxFeelerGridSide / params.feeler_zones);
  check("feelers_per_zone_side", params.feelers_per_zone_side, 1, 64);
  check("aimed_feelers_side", params.aimed_feelers_side, 0, 256);
  check("rays_per_zone_side", params.rays_per_zone_side, 1, kMaxRaysPerZoneSide);
  check("max_depth", params.max_depth, 1, 1000);
  check("sky_directions_side", params.sky_directions_side, 1, 64);
  check("roulette_depth", params.roulette_depth, 0, 1000);
  check("atlas_padding", params.atlas_padding, 2, 64);
  check("atlas_max_size", params.atlas_max_size, 16, 16384);
  check("filter_max_radius", params.filter_max_radius, 1, 64);
  check("pilot_divisor", params.pilot_divisor, 1, 64);
  if (!(params.filter_deposits >= 1.0f && params.filter_deposits <= 1e6f))
    throw std::invalid_argument("illumination: filter_deposits = " +
                                std::to_string(params.filter_deposits) + " is outside [1, 1e6]");
  if (!(params.texel_size >= 0.0f) || !std::isfinite(params.texel_size))
    throw std::invalid_argument("illumination: texel_size = " + std::to_string(params.texel_size) +
                                " must be a finite number >= 0 (0 = automatic)");
  if (!(params.chart_angle_deg > 0.0f && params.chart_angle_deg < 90.0f))
    throw std::invalid_argument("illumination: chart_angle_deg = " +
                                std::to_string(params.chart_angle_deg) + " is outside (0, 90)");
}

// ---- the pass in three steps: plan (lights, feelers, atlas, blocks), trace, finish ----------

struct IlluminationPass::Impl {
  const Scene& scene;
  const Accel& accel;
  IlluminationParams params;
  Clock::time_point start = Clock::now();
  double atlas_seconds = 0.0;
  LightSources sources;
  ZoneGrid grid;
  std::vector<LightSetup> setups;
  std::vector<WorkItem> items;
  std::vector<size_t> batch_start;  // batches of consecutive items, ~4096 rays each
  std::vector<uint64_t> batch_rays;
  uint64_t planned_rays = 0;
  Atlas atlas;
  FixedScale scale;
  IlluminationStats stats;  // the feelers' part; the rest comes from the sums
  size_t group_count = 0;   // light groups (bake/light_groups.h); 0: none

  Impl(const Scene& s, const Accel& a, const IlluminationParams& p, const Progress& progress)
      : scene(s), accel(a), params(p), sources(s) {
    check_illumination_params(params);
    set_up_lights();
    find_blocks(progress);
    run_pilot(progress);
    build_the_atlas();
    glm::dvec3 emitted(0.0);
    for (const LightSetup& setup : setups) emitted += glm::dvec3(setup.power);
    scale = fixed_scale(emitted, planned_rays);
  }

  int rays_side(const LightSetup& setup) const {
    return setup.rays_side > 0 ? setup.rays_side : grid.rays_side;
  }

  // One setup per light (area lights first, as before lamps existed, so their random streams
  // are unchanged), then lamps, then sky_directions_side^2 directions of the sky.
  void set_up_lights() {
    const std::vector<int> groups = light_group_of_sources(scene, sources, light_group_names(scene));
    std::vector<Sphere> specular_spheres = specular_bounds();
    grid.zones = params.feeler_zones;
    grid.sub = std::max(1, params.subzones_side);
    grid.rays_side = std::max(1, (params.rays_per_zone_side + grid.sub - 1) / grid.sub);
    for (size_t i = 0; i < sources.size(); ++i) {
      const size_t first_setup = setups.size();
      switch (sources.kind(i)) {
        case LightKind::area:
          setups.push_back(setup_light(scene, sources.area_light(i), specular_spheres));
          if (sources.area_light(i).two_sided) setups.push_back(split_off_back(setups.back()));
          break;
        case LightKind::point:
        case LightKind::spot:
        case LightKind::directional:
          if (sources.power(i) != vec3(0.0f)) setups.push_back(setup_lamp(sources, i));
          break;
        case LightKind::sky: {
          // Stratified directions drawn by the sky's own density (its radiance), each a batch
          // of parallel rays: unbiased over the draw, and as a whole it costs about one lamp's
          // rays (each direction gets 1/sky_directions_side of the rays per sub-zone side).
          const int n = params.sky_directions_side;
          Rng rng(hash_seed(params.seed, i, 0x5c7));
          for (int k = 0; k < n * n; ++k) {
            const vec2 u = stratified(k % n, k / n, n, n, rng.next_2d());
            LightSetup sky = setup_sky_direction(sources, i, u, n * n);
            sky.rays_side = std::max(1, (grid.rays_side + n - 1) / n);
            if (sky.power != vec3(0.0f)) setups.push_back(sky);
          }
          break;
        }
      }
      for (size_t k = first_setup; k < setups.size() && !groups.empty(); ++k)
        setups[k].group = groups[i];
    }
    group_count = light_group_names(scene).size();
    stats.zones_total =
        uint64_t(setups.size()) * uint64_t(params.feeler_zones * params.feeler_zones);
  }

  std::vector<Sphere> specular_bounds() const {
    std::vector<Sphere> spheres;
    for (const Mesh& mesh : scene.meshes)
      if (is_specular(scene.materials[size_t(mesh.material)]) && !mesh.positions.empty())
        spheres.push_back(bounding_sphere(mesh));
    return spheres;
  }

  // Feelers: which sub-zones of which light see a specular surface; then the blocks of dense
  // rays in them.
  void find_blocks(const Progress& progress) {
    const auto feeler_start = Clock::now();
    const std::vector<Sphere> specular_spheres = specular_bounds();
    const int zones = params.feeler_zones * params.feeler_zones;
    const int cells = grid.fine() * grid.fine();
    std::vector<std::vector<uint8_t>> traced(setups.size(), std::vector<uint8_t>(size_t(cells), 1));
    if (!params.trace_all_zones && !specular_spheres.empty()) {
      std::vector<uint64_t> casts(setups.size(), 0);
      tbb::parallel_for(size_t(0), setups.size(), [&](size_t l) {
        traced[l] = find_traced_cells(scene, accel, params, grid, setups[l], specular_spheres,
                                      hash_seed(params.seed, l, 0xfee1e7), casts[l]);
      });
      for (uint64_t c : casts) stats.feeler_rays += c;
    } else if (!params.trace_all_zones) {
      for (auto& t : traced) std::fill(t.begin(), t.end(), uint8_t(0));  // nothing to find
    }
    stats.feeler_seconds = seconds_since(feeler_start);
    progress.throw_if_cancelled();

    for (size_t l = 0; l < setups.size(); ++l) {
      const int m = rays_side(setups[l]);
      const int rows_per_block = std::max(1, 4096 / m);
      std::vector<uint8_t> zone_traced(size_t(zones), 0);
      for (int cell = 0; cell < cells; ++cell) {
        if (!traced[l][size_t(cell)]) continue;
        zone_traced[size_t(grid.zone_of_cell(cell))] = 1;
        for (int row = 0; row < m; row += rows_per_block)
          items.push_back({int(l), cell, row, std::min(rows_per_block, m - row)});
      }
      for (uint8_t t : zone_traced) stats.zones_traced += t;
    }
    // Items fix the random streams; batches of consecutive items (about 4096 rays) are the
    // tasks, so small sub-zones do not pay a task each. Neither depends on the thread count.
    for (size_t k = 0, rays = 4096; k < items.size(); ++k) {
      if (rays >= 4096) batch_start.push_back(k), batch_rays.push_back(0), rays = 0;
      const size_t item_rays =
          size_t(items[k].rows) * size_t(rays_side(setups[size_t(items[k].light)]));
      rays += item_rays;
      batch_rays.back() += item_rays;
      planned_rays += item_rays;
    }
    batch_start.push_back(items.size());
  }

  std::vector<bool> diffuse_meshes() const {
    std::vector<bool> diffuse(scene.meshes.size(), false);
    for (size_t m = 0; m < scene.meshes.size(); ++m)
      diffuse[m] = scene.materials[size_t(scene.meshes[m].material)].is_diffuse();
    return diffuse;
  }

  // The caustic pilot (IlluminationParams::pilot_texels): a texel size per diffuse mesh from
  // its densest caustic, in stats.pilot_texel_size. Deterministic: the pilot's deposits are
  // counted in block order, whatever thread traced them.
  void run_pilot(const Progress& progress) {
    const auto pilot_start = Clock::now();
    stats.pilot_texel_size.assign(scene.meshes.size(), 0.0f);
    stats.pilot_peak_density.assign(scene.meshes.size(), 0.0f);
    if (!params.pilot_texels || items.empty()) return;
    const std::vector<bool> diffuse = diffuse_meshes();
    const float base = params.texel_size > 0.0f
                           ? params.texel_size
                           : automatic_texel_size(scene, diffuse, params.atlas_max_size);
    const int d = params.pilot_divisor;
    ZoneGrid pilot_grid = grid;
    pilot_grid.rays_side = std::max(1, grid.rays_side / d);
    std::vector<LightSetup> pilot_setups = setups;
    for (LightSetup& setup : pilot_setups)
      if (setup.rays_side > 0) setup.rays_side = std::max(1, setup.rays_side / d);
    auto pilot_side = [&](int light) {
      const LightSetup& setup = pilot_setups[size_t(light)];
      return setup.rays_side > 0 ? setup.rays_side : pilot_grid.rays_side;
    };
    std::vector<WorkItem> pilot_items;  // one per traced sub-zone: its first block's
    for (const WorkItem& item : items)
      if (item.first_row == 0)
        pilot_items.push_back({item.light, item.cell, 0, pilot_side(item.light)});
    IlluminationParams pilot_params = params;
    pilot_params.seed = hash_seed(params.seed, 0x9170, 0);
    pilot_params.cast_log = nullptr;
    const Atlas no_atlas;
    const FixedScale no_scale{};
    Pass1Sums no_sums(0);
    const SplatTarget target{no_atlas, no_scale, no_sums, true};
    std::vector<BlockResult> found(pilot_items.size());
    tbb::parallel_for(size_t(0), pilot_items.size(), [&](size_t k) {
      if (progress.cancelled()) return;
      const WorkItem& item = pilot_items[k];
      found[k] = trace_block(scene, accel, pilot_params, pilot_grid,
                             pilot_setups[size_t(item.light)], item, target);
    });
    progress.throw_if_cancelled();

    // Deposits per cell of a grid of 4 base texels, weighted to the full ray count.
    const float cell = 4.0f * base;
    struct Count {
      double full = 0.0;
      uint32_t pilot = 0;
    };
    std::map<std::array<int64_t, 4>, Count> counts;
    for (size_t k = 0; k < found.size(); ++k) {
      const int light = pilot_items[k].light;
      const double full = double(rays_side(setups[size_t(light)])) / double(pilot_side(light));
      stats.pilot_rays += found[k].tally.rays;
      for (const PilotDeposit& deposit : found[k].deposits) {
        const glm::vec3 c = glm::floor(deposit.position / cell);
        Count& count = counts[{int64_t(deposit.mesh), int64_t(c.x), int64_t(c.y), int64_t(c.z)}];
        count.full += full * full;
        ++count.pilot;
        ++stats.pilot_deposits;
      }
    }
    // The densest cell of each mesh with at least 16 pilot deposits (25% noise); a plane
    // through a cube cell holds about cell^2 of surface.
    constexpr uint32_t kMinPilotDeposits = 16;
    for (const auto& [key, count] : counts) {
      float& peak = stats.pilot_peak_density[size_t(key[0])];
      if (count.pilot >= kMinPilotDeposits)
        peak = std::max(peak, float(count.full / (double(cell) * double(cell))));
    }
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
      const float density = stats.pilot_peak_density[m];
      if (!diffuse[m] || scene.meshes[m].bake.texel_size > 0.0f || !(density > 0.0f)) continue;
      // base / texel = 2^(steps / 2) with the texel still holding filter_deposits.
      const double ratio = double(base) * std::sqrt(double(density) / params.filter_deposits);
      const int steps = std::min(4, int(std::floor(2.0 * std::log2(std::max(1.0, ratio)))));
      if (steps > 0) stats.pilot_texel_size[m] = base / std::exp2(0.5f * float(steps));
    }
    stats.pilot_seconds = seconds_since(pilot_start);
  }

  // The atlas, for every diffuse mesh (the exported lightmap covers them all, caustic or not),
  // before the dense rays: they splat into it as they arrive.
  void build_the_atlas() {
    const auto atlas_start = Clock::now();
    const std::vector<bool> diffuse = diffuse_meshes();
    if (std::any_of(diffuse.begin(), diffuse.end(), [](bool b) { return b; })) {
      AtlasParams atlas_params;
      atlas_params.texel_size = params.texel_size;
      atlas_params.mesh_texel_size = stats.pilot_texel_size;
      atlas_params.max_size = params.atlas_max_size;
      atlas_params.padding = params.atlas_padding;
      atlas_params.chart_angle_deg = params.chart_angle_deg;
      atlas_params.generate_lightmap_uvs = params.generate_lightmap_uvs;
      atlas = build_atlas(scene, diffuse, atlas_params);
      for (const std::string& warning : atlas.warnings)
        std::fprintf(stderr, "lightbake: illumination atlas: %s\n", warning.c_str());
    }
    atlas_seconds += seconds_since(atlas_start);
  }

  void trace(Pass1Sums& sums, int shard, int shard_count, const Progress& progress) const {
    if (sums.nodes() != atlas.texel_area.size())
      throw std::invalid_argument("illumination: the sums do not match the pass's atlas");
    const std::vector<int> owner = pass1_batch_shards(batch_rays, shard_count);
    std::vector<size_t> mine;
    for (size_t b = 0; b < owner.size(); ++b)
      if (owner[b] == shard) mine.push_back(b);
    const SplatTarget target{atlas, scale, sums};
    std::vector<std::vector<Ray>> casts(params.cast_log ? items.size() : 0);
    ProgressCounter counter(progress, "illumination rays", mine.size());
    std::atomic<bool> stopped{false};
    tbb::parallel_for(size_t(0), mine.size(), [&](size_t k) {
      const size_t batch = mine[k];
      for (size_t i = batch_start[batch]; i < batch_start[batch + 1]; ++i) {
        if (stopped || progress.cancelled()) {
          stopped = true;
          return;
        }
        const WorkItem& item = items[i];
        BlockResult block =
            trace_block(scene, accel, params, grid, setups[size_t(item.light)], item, target);
        sums.add_tally_atomic(block.tally.to_fixed(scale));
        if (params.cast_log) casts[i] = std::move(block.casts);
      }
      counter.step();
    });
    progress.throw_if_cancelled();
    if (params.cast_log) {
      params.cast_log->clear();
      for (const std::vector<Ray>& c : casts)
        params.cast_log->insert(params.cast_log->end(), c.begin(), c.end());
    }
  }

  // The caustic map's L1 band (IlluminationParams::directional): each axis's L1 power through
  // map_of, the filter, radiance and dilation the power gets, then de-ringed against the map.
  // The density filter keeps light >= 0 (and each chart's total), so the signed L1 goes
  // through it as its positive and negative parts, each filtered with the same kernels (the
  // deposits' radii), and their difference is the band. The share s is 1 everywhere: caustic
  // light comes from few directions (a mirror's or a lens's image of the light), for which the
  // decode with W = 1 is the cosine law.
  template <class MapOf>
  static void make_l1(const Pass1Sums& sums, const MapOf& map_of, IlluminationMaps& maps) {
    for (size_t a = 0; a < 3; ++a) {
      const auto units = [&](size_t k, int c) { return sums.node_l1[9 * k + 3 * a + size_t(c)]; };
      maps.l1[a] = map_of([&](size_t k, int c) { return std::max<int64_t>(units(k, c), 0); });
      const std::vector<vec3> negative =
          map_of([&](size_t k, int c) { return std::max<int64_t>(-units(k, c), 0); });
      for (size_t k = 0; k < negative.size(); ++k) maps.l1[a][k] -= negative[k];
    }
    for (size_t k = 0; k < maps.radiance.size(); ++k)
      dering(maps.radiance[k], maps.l1[0][k], maps.l1[1][k], maps.l1[2][k]);
    maps.l1_share.assign(maps.radiance.size(), 1.0f);
  }

  IlluminationMaps finish(const Pass1Sums& sums, const Progress& progress) const {
    if (sums.nodes() != atlas.texel_area.size())
      throw std::invalid_argument("illumination: the sums do not match the pass's atlas");
    progress.update("illumination maps", 0.0);
    const auto maps_start = Clock::now();
    IlluminationMaps maps;
    maps.lightmap_uvs.resize(scene.meshes.size());
    maps.stats = stats;
    IlluminationStats& st = maps.stats;
    const FixedTally& t = sums.tally;
    auto power = [&](const int64_t(&units)[3]) {
      return vec3(glm::dvec3(double(units[0]), double(units[1]), double(units[2])) *
                  scale.power_unit);
    };
    int64_t mapped[3], absorbed[3];
    for (int c = 0; c < 3; ++c) {
      // Light on meshes the atlas had to leave out is lost to the maps: booked as absorbed.
      mapped[c] = t.deposited[c], absorbed[c] = t.absorbed[c];
      add_checked(mapped[c], -t.unmapped[c], "power deposited");
      add_checked(absorbed[c], t.unmapped[c], "power absorbed");
    }
    st.illumination_rays = t.rays;
    st.ray_casts = stats.feeler_rays + t.casts;
    st.power_sent = power(t.sent);
    st.power_deposited = power(mapped);
    st.power_absorbed = power(absorbed);
    st.power_escaped = power(t.escaped);
    st.power_direct = power(t.direct);
    st.emitter_hits = t.emitter_hits;
    st.rays_saved = rays_saved_by_feelers(st, params);
    // The formula assumes every light's full density; the sky's directions have less.
    const int zones = params.feeler_zones * params.feeler_zones;
    for (const LightSetup& setup : setups)
      if (setup.rays_side > 0) {
        const int64_t full = int64_t(grid.rays_side) * grid.sub,
                      own = int64_t(setup.rays_side) * grid.sub;
        st.rays_saved -= int64_t(zones) * (full * full - own * own);
      }

    if (atlas.width > 0) {
      const size_t nodes = sums.nodes();
      std::vector<double> node_deposits(nodes);
      for (size_t k = 0; k < nodes; ++k)
        node_deposits[k] = double(sums.node_weight[k]) * scale.weight_unit;
      // The map of the power units units(node, c): every group's map is filtered with the
      // kernels of all deposits, so the groups' maps add up to the whole map's.
      const auto map_of = [&](const auto& units) {
        std::vector<glm::dvec3> node_power(nodes);
        for (size_t k = 0; k < nodes; ++k)
          for (int c = 0; c < 3; ++c) node_power[k][c] = double(units(k, c)) * scale.power_unit[c];
        if (params.density_filter) {
          // A mesh whose texels the pilot refined holds >= filter_deposits deposits at its peak;
          // there the filter would only widen the caustic's sharp edge (IlluminationParams).
          std::vector<bool> raw(scene.meshes.size(), false);
          for (size_t m = 0; m < raw.size() && m < stats.pilot_texel_size.size(); ++m)
            raw[m] = params.pilot_skips_filter && stats.pilot_texel_size[m] > 0.0f;
          filter_by_density(atlas, node_deposits, params.filter_deposits, params.filter_max_radius,
                            node_power, raw);
        }
        std::vector<vec3> radiance = power_to_radiance(atlas, node_power);
        dilate(atlas, radiance, std::max(2, params.atlas_padding));
        return radiance;
      };
      maps.width = atlas.width;
      maps.height = atlas.height;
      maps.radiance = map_of([&](size_t k, int c) { return sums.node_power[3 * k + size_t(c)]; });
      if (!sums.node_l1.empty()) make_l1(sums, map_of, maps);
      for (size_t g = 0; g < sums.groups(); ++g)
        maps.group_radiance.push_back(
            map_of([&](size_t k, int c) { return sums.group_power.at(g, k, c); }));
      maps.texel_area = atlas.texel_area;
      maps.valid = atlas.valid;
      maps.lightmap_uvs = atlas.lightmap_uvs;
      maps.vertex_splits = atlas.vertex_splits;
      maps.texel_size = atlas.texel_size;
      maps.mesh_texel_size = atlas.mesh_texel_size;
    }
    progress.update("illumination maps", 1.0);
    st.atlas_seconds = atlas_seconds + seconds_since(maps_start);
    st.seconds = seconds_since(start);
    return maps;
  }
};

IlluminationPass::IlluminationPass(const Scene& scene, const Accel& accel,
                                   const IlluminationParams& params, const Progress& progress)
    : impl_(std::make_unique<Impl>(scene, accel, params, progress)) {}

IlluminationPass::~IlluminationPass() = default;

Pass1Sums IlluminationPass::empty_sums() const {
  return Pass1Sums(impl_->atlas.texel_area.size(), impl_->group_count,
                   impl_->params.directional);
}

void IlluminationPass::trace(Pass1Sums& sums, int shard, int shard_count,
                             const Progress& progress) const {
  if (!(shard_count >= 1 && shard >= 0 && shard < shard_count))
    throw std::invalid_argument("illumination: shard " + std::to_string(shard) + " of " +
                                std::to_string(shard_count));
  impl_->trace(sums, shard, shard_count, progress);
}

IlluminationMaps IlluminationPass::finish(const Pass1Sums& sums, const Progress& progress) const {
  return impl_->finish(sums, progress);
}

int IlluminationPass::atlas_width() const {
  return impl_->atlas.width;
}
int IlluminationPass::atlas_height() const {
  return impl_->atlas.height;
}
size_t IlluminationPass::batch_count() const {
  return impl_->batch_rays.size();
}
uint64_t IlluminationPass::planned_rays() const {
  return impl_->planned_rays;
}

std::vector<int> pass1_batch_shards(const std::vector<uint64_t>& batch_rays, int shard_count) {
  // Each batch to the shard with the fewest rays so far (the lowest index on a tie): balanced
  // to one batch (~4096 rays), and neighbouring batches, of similar cost, go to different
  // shards, so a costly light or zone is shared too.
  std::vector<int> owner(batch_rays.size(), 0);
  std::vector<uint64_t> load(size_t(std::max(1, shard_count)), 0);
  for (size_t b = 0; b < batch_rays.size(); ++b) {
    const size_t s = size_t(std::min_element(load.begin(), load.end()) - load.begin());
    owner[b] = int(s);
    load[s] += batch_rays[b];
  }
  return owner;
}

IlluminationMaps trace_illumination(const Scene& scene, const Accel& accel,
                                    const IlluminationParams& params, const Progress& progress) {
  const IlluminationPass pass(scene, accel, params, progress);
  Pass1Sums sums = pass.empty_sums();
  pass.trace(sums, 0, 1, progress);
  return pass.finish(sums, progress);
}

}  // namespace lb
