#include "bake/radiosity/radiosity.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <optional>
#include <queue>

#include "bake/bsdf.h"
#include "bake/lights.h"
#include "bake/sampling.h"
#include "bake/surface.h"

namespace lb {

namespace {

using glm::dvec3;

// Rays per block: the unit of parallel work and of seeding. Small, because most shots of a
// progressive solve carry a few hundred rays and must still spread over all cores.
constexpr size_t kBlockSize = 128;

double channel_sum(dvec3 v) {
  return v.x + v.y + v.z;
}

// Kensler's hash permutation of [0, length) ("Correlated Multi-Jittered Sampling", Pixar
// technical memo 13-01, 2013): pairs origin strata with direction strata at random but
// per ray, so no block depends on another.
uint32_t permute(uint32_t i, uint32_t length, uint32_t key) {
  uint32_t w = length - 1;
  w |= w >> 1, w |= w >> 2, w |= w >> 4, w |= w >> 8, w |= w >> 16;
  do {
    i ^= key;
    i *= 0xe170893du;
    i ^= key >> 16;
    i ^= (i & w) >> 4;
    i ^= key >> 8;
    i *= 0x0929eb3fu;
    i ^= key >> 23;
    i ^= (i & w) >> 1;
    i *= 1u | key >> 27;
    i *= 0x6935fa69u;
    i ^= (i & w) >> 11;
    i *= 0x74dcb303u;
    i ^= (i & w) >> 2;
    i *= 0x9e501cc3u;
    i ^= (i & w) >> 2;
    i *= 0xc860a3dfu;
    i &= w;
    i ^= i >> 5;
  } while (i >= length);
  return (i + key) % length;
}

struct Deposit {
  uint32_t patch;
  dvec3 incident;    // W arriving on the patch's front
  vec3 reflectance;  // R at the hit point (texture included)
};

struct BlockResult {
  std::vector<Deposit> deposits;
  dvec3 absorbed{0.0};  // by specular surfaces, back faces, non-patch surfaces, depth limit
  dvec3 escaped{0.0};
  uint64_t casts = 0;
};

struct Origin {
  vec3 position;
  vec3 normal;  // front side, unit: the hemisphere the rays leave into
};

class Shooter {
 public:
  Shooter(const Scene& traced, const Accel& accel, const Patches& patches, int max_depth)
      : scene_(traced), accel_(accel), patches_(patches), max_depth_(max_depth) {}

  // Sends n rays (rounded up to m*m) of total power `power` from origins drawn by
  // `sample_origin(u)`, cosine-distributed about the origin's normal. Results go to the first
  // `block_count` entries of `blocks`.
  struct Shot {
    uint64_t rays;
    size_t block_count;
  };
  template <class SampleOrigin>
  Shot shoot(uint64_t n, dvec3 power, uint64_t seed, uint64_t shot,
             const SampleOrigin& sample_origin, std::vector<BlockResult>& blocks) const {
    const uint64_t m = std::max<uint64_t>(1, uint64_t(std::ceil(std::sqrt(double(n)))));
    const uint64_t rays = m * m;
    const dvec3 ray_power = power / double(rays);
    const uint32_t key = uint32_t(hash_seed(seed, shot, 0xC0FFEE));
    const size_t block_count = size_t((rays + kBlockSize - 1) / kBlockSize);
    // Reuse the blocks' storage from shot to shot: most shots are small and frequent.
    if (blocks.size() < block_count) blocks.resize(block_count);
    for (size_t b = 0; b < block_count; ++b) {
      BlockResult& block = blocks[b];
      block.deposits.clear();
      block.absorbed = block.escaped = dvec3(0.0);
      block.casts = 0;
    }
    tbb::parallel_for(
        tbb::blocked_range<size_t>(0, block_count, 1),
        [&](const tbb::blocked_range<size_t>& range) {
          for (size_t b = range.begin(); b != range.end(); ++b) {
            Rng rng(hash_seed(seed, shot, b + 1));
            BlockResult& out = blocks[b];
            const uint64_t end = std::min<uint64_t>(rays, (b + 1) * kBlockSize);
            for (uint64_t j = b * kBlockSize; j < end; ++j) {
              const uint64_t o = permute(uint32_t(j), uint32_t(rays), key);
              const vec2 u_direction =
                  stratified(int(j % m), int(j / m), int(m), int(m), rng.next_2d());
              const vec2 u_origin =
                  stratified(int(o % m), int(o / m), int(m), int(m), rng.next_2d());
              const Origin origin = sample_origin(u_origin);
              const vec3 direction =
                  Frame(origin.normal).to_world(square_to_cosine_hemisphere(u_direction));
              Ray ray;
              ray.origin = offset_ray_origin(origin.position, origin.normal, direction);
              ray.direction = direction;
              trace(ray, ray_power, rng, out);
            }
          }
        });
    return {rays, block_count};
  }

 private:
  // One ray: through specular surfaces (k = k * weight) to the first diffuse patch.
  void trace(Ray ray, dvec3 power, Rng& rng, BlockResult& out) const {
    for (int depth = 0; depth <= max_depth_; ++depth) {
      const std::optional<Hit> hit = accel_.intersect(ray);
      ++out.casts;
      if (!hit) {
        out.escaped += power;
        return;
      }
      const Mesh& mesh = scene_.meshes[hit->mesh];
      const Material& material = scene_.materials[size_t(mesh.material)];
      if (material.is_diffuse()) {
        const PatchMesh& patch_mesh = patches_.meshes[hit->mesh];
        const bool front = glm::dot(ray.direction, hit->geometric_normal) < 0.0f;
        if (patch_mesh.triangle_patch.empty() || !front) {
          out.absorbed += power;
          return;
        }
        const vec3 reflectance = material.reflectance_texture < 0
                                     ? material.reflectance
                                     : reflectance_at(scene_, surface_at(scene_, *hit, ray));
        out.deposits.push_back({patch_mesh.triangle_patch[hit->triangle], power, reflectance});
        return;
      }
      const SurfacePoint sp = surface_at(scene_, *hit, ray);
      vec3 normal = sp.shading_normal;
      if (glm::dot(normal, sp.geometric_normal) < 0.0f) normal = -normal;
      const vec3 incident = glm::normalize(ray.direction);
      const auto scatter = scatter_specular(material, incident, normal, rng.next_2d());
      if (!scatter) {
        out.absorbed += power;
        return;
      }
      const dvec3 carried = power * dvec3(scatter->weight);
      out.absorbed += power - carried;
      power = carried;
      ray.origin = offset_ray_origin(sp.position, sp.geometric_normal, scatter->direction);
      ray.direction = scatter->direction;
      ray.tmin = 0.0f;
      ray.tmax = 1e30f;
    }
    out.absorbed += power;  // too many specular bounces
  }

  const Scene& scene_;
  const Accel& accel_;
  const Patches& patches_;
  int max_depth_;
};

// The patch with the most unsent power (sum of channels), ties to the lowest id: an indexed
// binary max-heap over all patches, so a shot costs O(touched * log patches), not O(patches).
class UnsentQueue {
 public:
  explicit UnsentQueue(size_t patch_count)
      : key_(patch_count, 0.0), heap_(patch_count), position_(patch_count) {
    for (size_t i = 0; i < patch_count; ++i) heap_[i] = position_[i] = uint32_t(i);
  }
  void update(uint32_t patch, double unsent) {
    const double old = key_[patch];
    key_[patch] = unsent;
    if (unsent > old)
      sift_up(position_[patch]);
    else
      sift_down(position_[patch]);
  }
  // The best patch, or nullopt when nothing is unsent.
  std::optional<uint32_t> top() const {
    if (heap_.empty() || !(key_[heap_[0]] > 0.0)) return std::nullopt;
    return heap_[0];
  }

 private:
  bool before(uint32_t a, uint32_t b) const {  // a belongs above b
    return key_[a] != key_[b] ? key_[a] > key_[b] : a < b;
  }
  void place(size_t i, uint32_t patch) {
    heap_[i] = patch;
    position_[patch] = uint32_t(i);
  }
  void sift_up(size_t i) {
    const uint32_t patch = heap_[i];
    while (i > 0 && before(patch, heap_[(i - 1) / 2])) {
      place(i, heap_[(i - 1) / 2]);
      i = (i - 1) / 2;
    }
    place(i, patch);
  }
  void sift_down(size_t i) {
    const uint32_t patch = heap_[i];
    const size_t n = heap_.size();
    while (true) {
      size_t child = 2 * i + 1;
      if (child >= n) break;
      if (child + 1 < n && before(heap_[child + 1], heap_[child])) ++child;
      if (!before(heap_[child], patch)) break;
      place(i, heap_[child]);
      i = child;
    }
    place(i, patch);
  }
  std::vector<double> key_;
  std::vector<uint32_t> heap_;
  std::vector<uint32_t> position_;
};

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Residual (recomputed exactly from the patches' unsent power) and the energy bookkeeping.
void store_energy_stats(const std::vector<dvec3>& unsent, dvec3 emitted, dvec3 absorbed,
                        dvec3 escaped, RadiosityStats& stats) {
  dvec3 residual(0.0);
  for (const dvec3& u : unsent) residual += u;
  stats.residual_unsent = vec3(residual);
  stats.residual_fraction = 0.0;
  for (int c = 0; c < 3; ++c)
    if (emitted[c] > 0.0)
      stats.residual_fraction = std::max(stats.residual_fraction, residual[c] / emitted[c]);
  stats.power_absorbed = vec3(absorbed);
  stats.power_escaped = vec3(escaped);
}

// Received patch power to per-vertex radiance in the stored convention (incident irradiance
// / pi), with each refined mesh: the final result and every partial one go through here.
void store_vertex_radiance(const Scene& scene, const Patches& patches,
                           const std::vector<dvec3>& received, VertexRadiosity& result) {
  const size_t patch_count = patches.patches.size();
  std::vector<vec3> patch_radiance(patch_count, vec3(0.0f));
  for (size_t p = 0; p < patch_count; ++p)
    if (patches.patches[p].area > 0.0)
      patch_radiance[p] = vec3(received[p] / (std::numbers::pi * patches.patches[p].area));

  result.meshes.assign(scene.meshes.size(), MeshRadiosity{});
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    const PatchMesh& patch_mesh = patches.meshes[m];
    if (patch_mesh.mesh.positions.empty()) continue;
    MeshRadiosity& out = result.meshes[m];
    out.mesh = patch_mesh.mesh;
    out.triangle_patch = patch_mesh.triangle_patch;
    out.vertex_radiance = vertex_radiance_from_patches(patch_mesh, patches.patches, patch_radiance);
  }
}

bool same_surface(const Scene& scene, const Patches& patches) {
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& refined = patches.meshes[m].mesh;
    if (refined.positions.empty()) continue;
    if (refined.positions != scene.meshes[m].positions ||
        refined.triangles != scene.meshes[m].triangles)
      return false;
  }
  return true;
}

}  // namespace

Scene refined_scene(const Scene& scene, const Patches& patches) {
  Scene traced = scene;
  for (size_t m = 0; m < scene.meshes.size(); ++m)
    if (!patches.meshes[m].mesh.positions.empty()) traced.meshes[m] = patches.meshes[m].mesh;
  return traced;
}

VertexRadiosity solve_radiosity(const Scene& scene, const Accel& accel,
                                const RadiosityParams& params, const Progress& progress,
                                const RadiosityCallbacks& callbacks) {
  const auto start = std::chrono::steady_clock::now();
  progress.update("radiosity: patches", 0.0);
  const Patches patches = build_patches(scene, params.patch_size, params.emitters_reflect);
  const size_t patch_count = patches.patches.size();

  // Trace the refined surface, so that a hit names its patch. When refinement changed nothing
  // the caller's accelerator already is that surface.
  std::optional<Scene> traced_scene;
  std::optional<Accel> traced_accel;
  const bool reuse = same_surface(scene, patches);
  if (!reuse) {
    traced_scene.emplace(refined_scene(scene, patches));
    traced_accel.emplace(*traced_scene);
  }
  const Scene& traced = reuse ? scene : *traced_scene;
  const Accel& tracer_accel = reuse ? accel : *traced_accel;
  const Shooter shooter(traced, tracer_accel, patches, params.max_specular_depth);

  VertexRadiosity result;
  RadiosityStats& stats = result.stats;
  stats.patch_count = patch_count;
  stats.setup_seconds = seconds_since(start);

  const std::vector<AreaLight> lights = collect_lights(scene);
  dvec3 emitted(0.0);
  for (const AreaLight& light : lights) emitted += dvec3(light.power);
  stats.power_emitted = vec3(emitted);

  // Rays per watt from the expected total power shot (geometric series in the mean albedo).
  double albedo_area = 0.0, area = 0.0;
  for (const Patch& patch : patches.patches) {
    const vec3 r = scene.materials[size_t(scene.meshes[patch.mesh].material)].reflectance;
    albedo_area += patch.area * (double(r.x) + r.y + r.z) / 3.0;
    area += patch.area;
  }
  const double mean_albedo = area > 0.0 ? std::min(albedo_area / area, 0.95) : 0.0;
  const double emitted_sum = channel_sum(emitted);
  const double rays_per_watt =
      emitted_sum > 0.0 ? double(params.ray_budget) * (1.0 - mean_albedo) / emitted_sum : 0.0;
  const uint64_t min_rays = std::max<uint64_t>(1, params.min_rays_per_shot);
  const uint64_t max_rays = params.max_rays > 0 ? params.max_rays : 4 * params.ray_budget;
  // Keeps m*m below 2^32 for the stratum permutation.
  const uint64_t shot_cap = uint64_t(65535) * 65535;
  auto rays_for = [&](dvec3 power) {
    const double wanted = std::ceil(channel_sum(power) * rays_per_watt);
    return std::clamp<uint64_t>(uint64_t(std::min(wanted, 1e18)), min_rays, shot_cap);
  };

  std::vector<std::vector<vec3>> triangle_normals(scene.meshes.size());
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& refined = patches.meshes[m].mesh;
    for (size_t t = 0; t < refined.triangles.size(); ++t)
      triangle_normals[m].push_back(triangle_normal(refined, t));
  }

  std::vector<dvec3> received(patch_count, dvec3(0.0));  // incident, counted (>= 2 diffuse)
  std::vector<dvec3> unsent(patch_count, dvec3(0.0));    // reflected, waiting to be shot
  dvec3 absorbed(0.0), escaped(0.0);
  dvec3 total_unsent(0.0);  // kept incrementally; recomputed exactly at the end
  UnsentQueue queue(patch_count);
  std::vector<BlockResult> blocks;
  std::vector<uint32_t> touched;
  std::vector<uint64_t> touched_in_shot(patch_count, ~uint64_t(0));
  uint64_t shot = 0;

  // Merges a shot's blocks in block order (the determinism of the sum lives here).
  auto merge = [&](Shooter::Shot done, bool count_received) {
    touched.clear();
    for (size_t b = 0; b < done.block_count; ++b) {
      const BlockResult& block = blocks[b];
      absorbed += block.absorbed;
      escaped += block.escaped;
      stats.ray_casts += block.casts;
      for (const Deposit& d : block.deposits) {
        const dvec3 r(d.reflectance);
        if (count_received) received[d.patch] += d.incident;
        unsent[d.patch] += r * d.incident;
        total_unsent += r * d.incident;
        absorbed += (1.0 - r) * d.incident;
        if (touched_in_shot[d.patch] != shot) {
          touched_in_shot[d.patch] = shot;
          touched.push_back(d.patch);
        }
      }
    }
    // The queue's order is total (power, then id), so update order does not matter.
    for (uint32_t p : touched) queue.update(p, channel_sum(unsent[p]));
  };

  // The solution so far to the caller's hook, at most as often as it asks. Reads only.
  auto last_partial_time = std::chrono::steady_clock::now();
  uint64_t last_partial_shots = 0;
  auto send_partial = [&] {
    if (stats.shots - last_partial_shots < callbacks.min_interval_shots ||
        seconds_since(last_partial_time) < callbacks.min_interval_seconds)
      return;
    VertexRadiosity partial;
    partial.stats = stats;
    store_energy_stats(unsent, emitted, absorbed, escaped, partial.stats);
    store_vertex_radiance(scene, patches, received, partial);
    partial.stats.converged = false;
    partial.stats.seconds = seconds_since(start);
    callbacks.on_partial(partial);
    last_partial_shots = stats.shots;
    last_partial_time = std::chrono::steady_clock::now();
  };

  // Nothing to shoot (no lights) or nowhere to put it (no diffuse surface): done already.
  if (patch_count == 0 || !(emitted_sum > 0.0)) stats.converged = true;
  if (patch_count > 0 && emitted_sum > 0.0) {
    // Lights first: what they deposit is direct (or direct-specular) light, which the viewer
    // and the illumination maps own. It becomes unsent power but is never counted.
    for (const AreaLight& light : lights) {
      progress.throw_if_cancelled();
      auto sample_light = [&](vec2 u) {
        const LightSample s = light.sample(scene, u);
        return Origin{s.position, s.normal};
      };
      const Shooter::Shot done = shooter.shoot(rays_for(dvec3(light.power)), dvec3(light.power),
                                               params.seed, shot, sample_light, blocks);
      stats.light_rays += done.rays;
      merge(done, false);
      ++shot;
    }

    const double log_target = std::log(std::max(params.convergence, 1e-300));
    double reported = -1.0;
    while (true) {
      progress.throw_if_cancelled();
      double fraction = 0.0;
      for (int c = 0; c < 3; ++c)
        if (emitted[c] > 0.0) fraction = std::max(fraction, total_unsent[c] / emitted[c]);
      if (fraction < params.convergence) {
        stats.converged = true;
        break;
      }
      if (stats.shots >= params.max_shots || stats.light_rays + stats.rays >= max_rays) break;
      const std::optional<uint32_t> source = queue.top();
      if (!source) break;

      const double converged_part = std::clamp(std::log(fraction) / log_target, 0.0, 1.0);
      if (converged_part - reported >= 0.01) {
        progress.update("radiosity", converged_part);
        reported = converged_part;
      }

      const Patch& patch = patches.patches[*source];
      const Mesh& refined = patches.meshes[patch.mesh].mesh;
      const dvec3 power = unsent[*source];
      unsent[*source] = dvec3(0.0);
      queue.update(*source, 0.0);
      total_unsent -= power;
      const std::vector<vec3>& normals = triangle_normals[patch.mesh];
      auto sample_patch_origin = [&](vec2 u) {
        const PatchSample s = sample_patch(patch, refined, u);
        return Origin{s.position, normals[s.triangle]};
      };
      const Shooter::Shot done =
          shooter.shoot(rays_for(power), power, params.seed, shot, sample_patch_origin, blocks);
      stats.rays += done.rays;
      ++stats.shots;
      merge(done, true);
      ++shot;
      if (callbacks.on_partial) send_partial();
    }
  }

  store_energy_stats(unsent, emitted, absorbed, escaped, stats);
  store_vertex_radiance(scene, patches, received, result);
  stats.seconds = seconds_since(start);
  progress.update("radiosity", 1.0);
  return result;
}

double mean_relative_error(const VertexRadiosity& a, const VertexRadiosity& reference) {
  double sum = 0.0;
  size_t count = 0;
  for (size_t m = 0; m < a.meshes.size(); ++m)
    for (size_t v = 0; v < a.meshes[m].vertex_radiance.size(); ++v)
      for (int c = 0; c < 3; ++c) {
        const double ref = reference.meshes[m].vertex_radiance[v][c];
        if (ref <= 0.0) continue;
        sum += std::abs(a.meshes[m].vertex_radiance[v][c] - ref) / ref;
        ++count;
      }
  return count ? sum / double(count) : 1.0;
}

}  // namespace lb
