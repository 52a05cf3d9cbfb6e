#include "bake/radiosity/radiosity.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <optional>
#include <queue>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "bake/bsdf.h"
#include "bake/bump.h"
#include "bake/light_groups.h"
#include "bake/light_sources.h"
#include "bake/radiosity/shot_sampling.h"
#include "bake/sampling.h"
#include "bake/surface.h"
#include "bake/work_limits.h"

namespace lb {

namespace {

using glm::dvec3;

// Rays per block: the unit of parallel work and of seeding. Small, because most shots of a
// progressive solve carry a few hundred rays and must still spread over all cores.
constexpr size_t kBlockSize = 128;
// Embree's stream API gets each block's rays as one wave, flagged incoherent: a block's
// directions are neighbouring strata, but their origins are spread over the whole patch or
// light by the random pairing, and packets (the coherent flag) measured ~5% slower
// (bench_radiosity BM_PassOnly, docs/radiosity.md).
constexpr bool kCoherent = false;

double channel_sum(dvec3 v) {
  return v.x + v.y + v.z;
}

// A bump-mapped surface's irradiance is the incident radiance weighted by the cosine to its
// bumped normal, over the surface's own hemisphere (what HQ's direct light, the final gather
// and the reference integrate): a ray arriving from `towards_source` carries cos_bumped /
// cos_flat of the flat surface's share. Under uniform light a normal tilted alpha receives
// (1 + cos alpha) / 2 of the flat irradiance. The weight grows without bound toward grazing
// rays (its variance diverges logarithmically), so it is capped: at 32 the cap's bias is
// 0.01% under a constant sky at alpha = 26.6 degrees, at 16 it was 0.3%, at 4 1.8%
// (RadiositySky.BumpedFloorReceivesItsSkyViewFactor).
constexpr double kMaxBumpWeight = 32.0;

double bump_weight(const Scene& scene, const SurfacePoint& sp, const Hit& hit, const Ray& ray) {
  const vec3 towards_source = -glm::normalize(ray.direction);
  vec3 bumped = bumped_normal(scene, sp);  // a front hit: the mesh's side, as receiver_at
  if (glm::dot(bumped, hit.geometric_normal) <= 0.0f) bumped = hit.geometric_normal;
  const double cos_flat = glm::dot(towards_source, hit.geometric_normal);
  const double cos_bumped = std::max(glm::dot(towards_source, bumped), 0.0f);
  if (!(cos_flat > 0.0)) return 0.0;
  return std::min(cos_bumped / cos_flat, kMaxBumpWeight);
}

// Origin strata are paired with direction strata by a random permutation per shot: a table
// shuffled up front (one random draw and swap per ray) up to this many rays, Kensler's hash
// permutation beyond (the table would be too big). Hashing every ray (a rejection loop of
// six multiplies and mispredicted exits) made the whole pass ~1.5x slower (BM_PassOnly).
constexpr uint64_t kPairingTableLimit = uint64_t(1) << 22;

// The table: entry j is the origin stratum (column | row << 16) of direction stratum j of a
// side x side grid, a uniformly random permutation (Fisher-Yates).
void shuffle_pairing(uint32_t side, uint64_t key, std::vector<uint32_t>& pairing) {
  const uint32_t count = side * side;
  pairing.resize(count);
  uint32_t k = 0;
  for (uint32_t row = 0; row < side; ++row)
    for (uint32_t column = 0; column < side; ++column) pairing[k++] = column | row << 16;
  for (uint32_t i = count - 1; i > 0; --i) {
    const uint64_t bits = mix64(key + i * 0x9e3779b97f4a7c15ULL);
    const uint32_t j = uint32_t((uint64_t(uint32_t(bits)) * (uint64_t(i) + 1)) >> 32);
    std::swap(pairing[i], pairing[j]);
  }
}

// Kensler's hash permutation of [0, length) ("Correlated Multi-Jittered Sampling", Pixar
// technical memo 13-01, 2013), for shots too big to tabulate: pairs strata at random but
// per ray, so no block depends on another. `offset` = key % length, hoisted per shot.
uint32_t permute(uint32_t i, uint32_t length, uint32_t key, uint32_t offset) {
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
  i += offset;  // both < length
  return i >= length ? i - length : i;
}

struct Deposit {
  uint32_t patch;
  bool via_specular;  // met a mirror, glass or glossy metal on the way (a caustic of a light)
  bool back = false;  // on the back of a two-sided surface (Material::two_sided_reflection)
  dvec3 incident;     // W arriving on the patch's front (its back when `back`)
  vec3 reflectance;   // R at the hit point (texture included)
};

struct BlockResult {
  std::vector<Deposit> deposits;
  dvec3 sent{0.0};      // the power of the block's rays as they left the source
  dvec3 missed{0.0};    // the part of `escaped` that hit nothing at all
  dvec3 absorbed{0.0};  // by specular surfaces, back faces, non-patch surfaces, depth limit
  dvec3 escaped{0.0};
  uint64_t casts = 0;
  std::vector<Ray> cast_log;  // only when the caller asked for it
};

// What a shot leaves from (a light or a patch), set up once per shot so that drawing a ray's
// origin costs a few multiply-adds: each triangle as corner and edges with its frame (about
// the front normal, which the rays leave into), and the area CDF over the triangles.
struct SourceTriangle {
  vec3 corner, edge1, edge2;
  Frame frame{vec3(0.0f, 0.0f, 1.0f)};
  // The triangle's slice [cdf_low, cdf_low + 1 / inverse_width) of the area CDF.
  float cdf_low = 0.0f, inverse_width = 1.0f;
};
struct Source {
  std::vector<SourceTriangle> triangles;
  std::vector<float> cdf;  // area CDF over `triangles`, last 1
  bool two_sided = false;  // a two-sided light: half the rays leave from the back
  bool back = false;       // every ray leaves from the back (a two-sided patch's back power)

  void set(const Mesh& mesh, const std::vector<uint32_t>& ids, const std::vector<float>& area_cdf,
           const std::vector<vec3>& normals) {
    triangles.resize(ids.size());
    for (size_t i = 0; i < ids.size(); ++i) {
      const uvec3 tri = mesh.triangles[ids[i]];
      SourceTriangle& out = triangles[i];
      out.corner = mesh.positions[tri.x];
      out.edge1 = mesh.positions[tri.y] - out.corner;
      out.edge2 = mesh.positions[tri.z] - out.corner;
      out.frame = Frame(normals[i]);
      out.cdf_low = i == 0 ? 0.0f : area_cdf[i - 1];
      const float width = area_cdf[i] - out.cdf_low;
      out.inverse_width = width > 0.0f ? 1.0f / width : 0.0f;
    }
    cdf = area_cdf;
  }

  // A point uniform by area and the triangle it lies on, from u in [0,1)^2: u.x picks the
  // triangle and is reused inside it (stratified in, stratified out), as AreaLight::sample.
  const SourceTriangle& sample(vec2 u, vec3& position) const {
    const size_t count = triangles.size();
    size_t index = 0;
    if (count > 1) {
      // The first entry >= u.x; a patch has a few triangles, so count without branches.
      if (count <= 16) {
        for (size_t i = 0; i + 1 < count; ++i) index += cdf[i] < u.x;
      } else {
        index = std::min(size_t(std::lower_bound(cdf.begin(), cdf.end(), u.x) - cdf.begin()),
                         count - 1);
      }
      const SourceTriangle& tri = triangles[index];
      u.x = std::clamp((u.x - tri.cdf_low) * tri.inverse_width, 0.0f, 0.99999994f);
    }
    const SourceTriangle& tri = triangles[index];
    const vec2 b = square_to_triangle(u);
    position = tri.corner + b.x * tri.edge1 + b.y * tri.edge2;
    return tri;
  }
};

// A light that is not a mesh (lamp, sky) shooting through LightSources::emit: each ray brings
// its own power (a spot's falloff, the sky's radiance over its pdf), and a lamp with a range
// fades by its window at the first hit.
struct EmitterSource {
  const LightSources* lights = nullptr;
  size_t light = 0;
};

// Rays traced together: one block's, then their specular survivors, wave by wave.
constexpr size_t kWave = kBlockSize;
// Blocks traced between two merges (and two cancellation checks) of one shot.
constexpr size_t kChunkBlocks = 1024;

class Shooter {
 public:
  Shooter(const Scene& traced, const Accel& accel, const Patches& patches, int max_depth,
          bool log_casts)
      : scene_(traced),
        accel_(accel),
        patches_(patches),
        max_depth_(max_depth),
        log_casts_(log_casts) {}

  // Sends n rays (rounded up to m*m) of total power `power` from `source`, cosine-distributed
  // about its normal, and returns m*m. The blocks are traced in chunks of at most kChunkBlocks,
  // in block order: after each chunk `merge(chunk)` finds its results in the first
  // chunk.block_count entries of `blocks`. So memory stays bounded whatever n is, and a
  // cancel is seen within a chunk (~131k rays, a few tens of milliseconds).
  struct Shot {
    uint64_t rays;
    size_t block_count;
  };
  // With an EmitterSource the rays come from LightSources::emit with the same strata, each
  // carrying its emitted power / (m*m) (whose mean is `power` / (m*m)).
  template <class Merge, class S>
  uint64_t shoot(uint64_t n, dvec3 power, uint64_t seed, uint64_t shot, const S& source,
                 std::vector<BlockResult>& blocks, std::vector<uint32_t>& pairing,
                 const Progress& progress, Merge&& merge) const {
    const uint64_t m = std::max<uint64_t>(1, uint64_t(std::ceil(std::sqrt(double(n)))));
    const uint64_t rays = m * m;
    const dvec3 ray_power = power / double(rays);
    const uint64_t key = hash_seed(seed, shot, 0xC0FFEE);
    const bool tabulated = rays <= kPairingTableLimit;
    if (tabulated) shuffle_pairing(uint32_t(m), key, pairing);
    const uint32_t key32 = uint32_t(key), offset = uint32_t(key32 % rays);
    const size_t block_count = size_t((rays + kBlockSize - 1) / kBlockSize);
    size_t chunk_begin = 0;
    auto shoot_blocks = [&](const tbb::blocked_range<size_t>& range) {
      std::array<Ray, kWave> wave;
      std::array<dvec3, kWave> powers;
      struct {
        float u_x[kWave], u_y[kWave], local_x[kWave], local_y[kWave], local_z[kWave];
        vec2 u_origin[kWave];
        float side[kWave];
      } scratch;
      const uint32_t side = uint32_t(m);
      const float inverse_side = 1.0f / float(side);
      const double inverse_side_exact = 1.0 / double(side);
      for (size_t b = range.begin(); b != range.end(); ++b) {
        const uint64_t block_key = hash_seed(seed, shot, b + 1);
        const uint64_t first = b * kBlockSize;
        const size_t count = size_t(std::min<uint64_t>(rays, first + kBlockSize) - first);
        uint32_t column = uint32_t(first % side), row = uint32_t(first / side);
        // Three sweeps over the wave: the strata, then the cosine map alone (branch-free,
        // so the compiler runs it 4 rays at a time), then origins and the rays themselves.
        for (size_t k = 0; k < count; ++k) {
          // Direction stratum j = first + k walks the grid row by row; the origin stratum
          // is its partner.
          const uint32_t j = uint32_t(first + k);
          uint32_t o_column, o_row;
          if (tabulated) {
            o_column = pairing[j] & 0xffffu;
            o_row = pairing[j] >> 16;
          } else {
            // Exact for o < 2^32: the quotient's fraction is at least 1/(2 side).
            const uint32_t o = permute(j, uint32_t(rays), key32, offset);
            o_row = uint32_t((double(o) + 0.5) * inverse_side_exact);
            o_column = o - o_row * side;
          }
          const uint64_t bits = mix64(block_key + k * 0x9e3779b97f4a7c15ULL);
          const vec2 u_direction =
              shot::jittered_stratum(column, row, inverse_side, uint32_t(bits));
          scratch.u_x[k] = u_direction.x;
          scratch.u_y[k] = u_direction.y;
          scratch.u_origin[k] =
              shot::jittered_stratum(o_column, o_row, inverse_side, uint32_t(bits >> 32));
          if (++column == side) column = 0, ++row;
        }
        if constexpr (std::is_same_v<S, EmitterSource>) {
          const double inverse_rays = 1.0 / double(rays);
          for (size_t k = 0; k < count; ++k) {
            const EmittedRay e = source.lights->emit(source.light, scratch.u_origin[k],
                                                     vec2(scratch.u_x[k], scratch.u_y[k]));
            Ray& ray = wave[k];
            ray.origin = e.origin;
            ray.direction = e.direction;
            ray.tmin = 0.0f;
            ray.tmax = 1e30f;
            powers[k] = dvec3(e.power) * inverse_rays;
          }
        } else {
          if (source.two_sided)
            for (size_t k = 0; k < count; ++k)
              scratch.side[k] = pick_emitting_side(true, scratch.u_x[k]);
          for (size_t k = 0; k < count; ++k) {
            const vec3 d = square_to_cosine_hemisphere(vec2(scratch.u_x[k], scratch.u_y[k]));
            scratch.local_x[k] = d.x;
            scratch.local_y[k] = d.y;
            scratch.local_z[k] = d.z;
          }
          if (source.two_sided)
            for (size_t k = 0; k < count; ++k) scratch.local_z[k] *= scratch.side[k];
          if (source.back)
            for (size_t k = 0; k < count; ++k) scratch.local_z[k] = -scratch.local_z[k];
          for (size_t k = 0; k < count; ++k) {
            vec3 position;
            const SourceTriangle& tri = source.sample(scratch.u_origin[k], position);
            Ray& ray = wave[k];  // written in place: a copied temporary stalls the store
            ray.direction = tri.frame.to_world(
                vec3(scratch.local_x[k], scratch.local_y[k], scratch.local_z[k]));
            ray.origin = offset_ray_origin(position, tri.frame.normal, ray.direction);
            ray.tmin = 0.0f;
            ray.tmax = 1e30f;
          }
          std::fill_n(powers.begin(), count, ray_power);
        }
        // Specular bounces draw from their own generator, seeded per block.
        Rng rng(mix64(block_key));
        const LightSources* windowed = nullptr;
        size_t window_light = 0;
        if constexpr (std::is_same_v<S, EmitterSource>)
          windowed = source.lights, window_light = source.light;
        trace(wave.data(), count, powers, rng, blocks[b - chunk_begin], windowed, window_light);
      }
    };
    for (; chunk_begin < block_count; chunk_begin += kChunkBlocks) {
      progress.throw_if_cancelled();
      const size_t chunk_end = std::min(block_count, chunk_begin + kChunkBlocks);
      // Reuse the blocks' storage from shot to shot: most shots are small and frequent.
      if (blocks.size() < chunk_end - chunk_begin) blocks.resize(chunk_end - chunk_begin);
      for (size_t b = 0; b < chunk_end - chunk_begin; ++b) {
        BlockResult& block = blocks[b];
        block.deposits.clear();
        block.absorbed = block.escaped = block.sent = block.missed = dvec3(0.0);
        block.casts = 0;
        block.cast_log.clear();
      }
      tbb::parallel_for(tbb::blocked_range<size_t>(chunk_begin, chunk_end, 1), shoot_blocks);
      const uint64_t chunk_rays =
          std::min<uint64_t>(rays, chunk_end * kBlockSize) - chunk_begin * kBlockSize;
      merge(Shot{chunk_rays, chunk_end - chunk_begin});
    }
    return rays;
  }

 private:
  // `count` rays of power `powers`, through specular surfaces (k = k * weight) to the first
  // diffuse patch, one wave of Embree's stream API per bounce; `rays` and `powers` are
  // overwritten. With `windowed`, light `window_light`'s range window fades each ray at its
  // first hit (a miss travels an infinite distance); the faded power is booked as absorbed.
  void trace(Ray* rays, size_t count, std::array<dvec3, kWave>& powers, Rng& rng, BlockResult& out,
             const LightSources* windowed, size_t window_light) const {
    std::array<std::optional<Hit>, kWave> hits;
    for (size_t k = 0; k < count; ++k) out.sent += powers[k];
    size_t live = count;
    for (int depth = 0; live > 0; ++depth) {
      if (depth > max_depth_) {  // too many specular bounces
        for (size_t k = 0; k < live; ++k) out.absorbed += powers[k];
        return;
      }
      if (log_casts_) out.cast_log.insert(out.cast_log.end(), rays, rays + live);
      accel_.intersect_many(rays, live, hits.data(), kCoherent);
      out.casts += live;
      size_t survivors = 0;
      for (size_t k = 0; k < live; ++k) {
        dvec3 power = powers[k];
        if (depth == 0 && windowed) {
          const float distance = hits[k] ? hits[k]->t : std::numeric_limits<float>::infinity();
          const dvec3 kept = power * double(windowed->range_window(window_light, distance));
          out.absorbed += power - kept;
          power = kept;
        }
        if (!hits[k]) {
          out.escaped += power;
          if (depth == 0) out.missed += power;
          continue;
        }
        const Hit& hit = *hits[k];
        const Ray& ray = rays[k];
        const Mesh& mesh = scene_.meshes[hit.mesh];
        const Material& material = scene_.materials[size_t(mesh.material)];
        if (material.is_diffuse()) {
          const PatchMesh& patch_mesh = patches_.meshes[hit.mesh];
          const bool front = glm::dot(ray.direction, hit.geometric_normal) < 0.0f;
          if (patch_mesh.triangle_patch.empty() || (!front && !material.two_sided_reflection)) {
            out.absorbed += power;
            continue;
          }
          Deposit& deposit = out.deposits.emplace_back();
          deposit.patch = patch_mesh.triangle_patch[hit.triangle];
          deposit.via_specular = depth > 0;
          deposit.back = !front;
          deposit.incident = power;
          deposit.reflectance = material.reflectance;
          const bool textured = material.reflectance_texture >= 0;
          const bool bumped = material.bump != BumpKind::none && front;
          if (textured || bumped) {  // the surface point, built once for both
            const SurfacePoint sp = surface_at(scene_, hit, ray);
            if (textured) deposit.reflectance = reflectance_at(scene_, sp);
            if (bumped) {
              // What the bump turns away never arrives: absorbed in the books (it may be
              // negative where the bump faces the ray; the sum over the surface is not).
              deposit.incident = power * bump_weight(scene_, sp, hit, ray);
              out.absorbed += power - deposit.incident;
            }
          }
          continue;
        }
        const SurfacePoint sp = surface_at(scene_, hit, ray);
        const vec3 incident = glm::normalize(ray.direction);
        const auto scatter = scatter_specular(material, incident,
                                              specular_normal(scene_, sp, incident), rng.next_2d());
        if (!scatter) {
          out.absorbed += power;
          continue;
        }
        const dvec3 carried = power * dvec3(scatter->weight);
        out.absorbed += power - carried;
        Ray& next = rays[survivors];  // survivors <= k: the wave compacts in place
        next.origin = offset_ray_origin(sp.position, sp.geometric_normal, scatter->direction);
        next.direction = scatter->direction;
        next.tmin = 0.0f;
        next.tmax = 1e30f;
        powers[survivors] = carried;
        ++survivors;
      }
      live = survivors;
    }
  }

  const Scene& scene_;
  const Accel& accel_;
  const Patches& patches_;
  int max_depth_;
  bool log_casts_;
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
void store_energy_stats(const std::vector<dvec3>& unsent, dvec3 reference, dvec3 absorbed,
                        dvec3 escaped, RadiosityStats& stats) {
  dvec3 residual(0.0);
  for (const dvec3& u : unsent) residual += u;
  stats.residual_unsent = vec3(residual);
  stats.residual_fraction = 0.0;
  for (int c = 0; c < 3; ++c)
    if (reference[c] > 0.0)
      stats.residual_fraction = std::max(stats.residual_fraction, residual[c] / reference[c]);
  stats.power_absorbed = vec3(absorbed);
  stats.power_escaped = vec3(escaped);
}

// Received patch power to per-vertex radiance in the stored convention (incident irradiance
// / pi), with each refined mesh: the final result and every partial one go through here.
// Per scene mesh, the vertex radiance of the received patch power (empty where no patches).
std::vector<std::vector<vec3>> mesh_vertex_radiance(const Scene& scene, const Patches& patches,
                                                    const std::vector<dvec3>& received) {
  const size_t patch_count = patches.patches.size();
  std::vector<vec3> patch_radiance(patch_count, vec3(0.0f));
  for (size_t p = 0; p < patch_count; ++p)
    if (patches.patches[p].area > 0.0)
      patch_radiance[p] = vec3(received[p] / (std::numbers::pi * patches.patches[p].area));
  std::vector<std::vector<vec3>> out(scene.meshes.size());
  for (size_t m = 0; m < scene.meshes.size(); ++m)
    if (!patches.meshes[m].mesh.positions.empty())
      out[m] = vertex_radiance_from_patches(patches.meshes[m], patches.patches, patch_radiance);
  return out;
}

void store_vertex_radiance(const Scene& scene, const Patches& patches,
                           const std::vector<dvec3>& received, VertexRadiosity& result) {
  std::vector<std::vector<vec3>> radiance = mesh_vertex_radiance(scene, patches, received);
  result.meshes.assign(scene.meshes.size(), MeshRadiosity{});
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    const PatchMesh& patch_mesh = patches.meshes[m];
    if (patch_mesh.mesh.positions.empty()) continue;
    MeshRadiosity& out = result.meshes[m];
    out.mesh = patch_mesh.mesh;
    out.triangle_patch = patch_mesh.triangle_patch;
    out.vertex_radiance = std::move(radiance[m]);
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

void check_radiosity_params(const Scene& scene, const RadiosityParams& params) {
  auto fail = [](const std::string& message) {
    throw std::invalid_argument("radiosity: " + message);
  };
  if (!(params.patch_size >= 0.0f) || !std::isfinite(params.patch_size))
    fail("patch_size = " + std::to_string(params.patch_size) +
         " must be a finite number >= 0 (0 = automatic)");
  if (params.ray_budget < 1 || params.ray_budget > kMaxRadiosityRayBudget)
    fail("ray_budget = " + std::to_string(params.ray_budget) + " is outside [1, " +
         std::to_string(kMaxRadiosityRayBudget) + "] (the cap is about 6 hours of rays here)");
  if (params.max_rays > 4 * kMaxRadiosityRayBudget)
    fail("max_rays = " + std::to_string(params.max_rays) + " is over the cap of " +
         std::to_string(4 * kMaxRadiosityRayBudget));
  if (!(params.convergence >= 0.0 && params.convergence <= 1.0))
    fail("convergence = " + std::to_string(params.convergence) + " is outside [0, 1]");
  if (params.max_specular_depth < 0 || params.max_specular_depth > 1000)
    fail("max_specular_depth = " + std::to_string(params.max_specular_depth) +
         " is outside [0, 1000]");
  const double patches = estimate_patch_count(scene, params.patch_size, params.emitters_reflect);
  char estimate[96];
  std::snprintf(estimate, sizeof estimate, "patch_size %g m gives about %.3g patches",
                double(params.patch_size > 0.0f ? params.patch_size : automatic_patch_size(scene)),
                patches);
  if (patches > kMaxRadiosityPatches)
    fail(std::string(estimate) + ", over the cap of " + std::to_string(int(kMaxRadiosityPatches)) +
         ": raise the patch size");
  // Each patch: its record, ~2 refined triangles with their vertices, and the solver's arrays.
  require_memory("radiosity: " + std::string(estimate) + ", which", patches * 600.0);
}

VertexRadiosity solve_radiosity(const Scene& scene, const Accel& accel,
                                const RadiosityParams& params, const Progress& progress,
                                const RadiosityCallbacks& callbacks) {
  check_radiosity_params(scene, params);
  const auto start = std::chrono::steady_clock::now();
  progress.update("radiosity: patches", 0.0);
  const Patches patches =
      build_patches(scene, params.patch_size, params.emitters_reflect,
                    params.contact_cuts ? &accel : nullptr, params.contact_cuts, &progress);
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
  const Shooter shooter(traced, tracer_accel, patches, params.max_specular_depth,
                        callbacks.cast_log != nullptr);

  VertexRadiosity result;
  RadiosityStats& stats = result.stats;
  stats.patch_count = patch_count;
  stats.setup_seconds = seconds_since(start);

  const LightSources lights(scene);
  dvec3 emitted(0.0);
  for (size_t i = 0; i < lights.size(); ++i) emitted += dvec3(lights.power(i));
  stats.power_emitted = vec3(emitted);
  // The power convergence is measured against: emitted, less what lamps and the sky sent past
  // the scene (set after the lights' shots).
  dvec3 reference = emitted;

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
  const uint64_t max_shots = params.max_shots > 0
                                 ? params.max_shots
                                 : std::max<uint64_t>(100'000, 128 * uint64_t(patch_count));
  const uint64_t max_rays =
      params.max_rays > 0 ? params.max_rays : 4 * params.ray_budget + 2 * min_rays * max_shots;
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
  // Reflected by the back of two-sided surfaces (Material::two_sided_reflection), shot from
  // the back; empty of power elsewhere.
  std::vector<dvec3> unsent_back(patch_count, dvec3(0.0));
  // Both sides' unsent power, for the books.
  auto all_unsent = [&] {
    std::vector<dvec3> sum(unsent);
    for (size_t p = 0; p < patch_count; ++p) sum[p] += unsent_back[p];
    return sum;
  };
  dvec3 absorbed(0.0), escaped(0.0);
  dvec3 total_unsent(0.0);  // kept incrementally; recomputed exactly at the end
  UnsentQueue queue(patch_count);
  std::vector<BlockResult> blocks;
  Source shot_source;
  std::vector<uint32_t> pairing;
  std::vector<vec3> patch_normals;
  std::vector<uint32_t> touched;
  std::vector<uint64_t> touched_in_merge(patch_count, ~uint64_t(0));
  uint64_t merges = 0;
  uint64_t shot = 0;
  dvec3 sent(0.0);    // by every shot so far
  dvec3 missed(0.0);  // of it, the part that hit nothing (summed, used for lamps and the sky)

  // Light groups (bake/light_groups.h): each group's part of every patch's received and unsent
  // power. Shots are chosen and their rays drawn from the totals, as without groups; each
  // deposit is split between the groups in the proportion, per channel, of the power the shot
  // carried from each (`share`): deposits are linear in the shot's power, so every group gets
  // the deposits of its own power along the same rays.
  const std::vector<std::string> group_names = light_group_names(scene);
  const size_t groups = group_names.size();
  const std::vector<int> light_group = light_group_of_sources(scene, lights, group_names);
  using GroupLedger = std::vector<std::vector<dvec3>>;  // [group][patch]
  GroupLedger group_received(groups, std::vector<dvec3>(patch_count, dvec3(0.0)));
  GroupLedger group_unsent = group_received, group_unsent_back = group_received;
  std::vector<dvec3> share(groups, dvec3(0.0));
  // The shot's share from each group's part of `ledger`'s power at `patch` (taken out of it).
  auto take_share = [&](GroupLedger& ledger, uint32_t patch) {
    dvec3 total(0.0);
    for (size_t g = 0; g < groups; ++g) total += ledger[g][patch];
    for (size_t g = 0; g < groups; ++g) {
      for (int c = 0; c < 3; ++c)
        share[g][c] = total[c] > 0.0 ? ledger[g][patch][c] / total[c] : 0.0;
      ledger[g][patch] = dvec3(0.0);
    }
  };

  // Merges a shot's blocks in block order (the determinism of the sum lives here).
  // `count`: which deposits are soft light (received), see the lights' shots below.
  enum class Count { none, all, direct };
  auto merge = [&](Shooter::Shot done, Count count) {
    touched.clear();
    for (size_t b = 0; b < done.block_count; ++b) {
      const BlockResult& block = blocks[b];
      absorbed += block.absorbed;
      escaped += block.escaped;
      sent += block.sent;
      missed += block.missed;
      stats.ray_casts += block.casts;
      if (callbacks.cast_log)
        callbacks.cast_log->insert(callbacks.cast_log->end(), block.cast_log.begin(),
                                   block.cast_log.end());
      for (const Deposit& d : block.deposits) {
        const dvec3 r(d.reflectance);
        // A back's light is reflected from the back and never shown: the stored radiosity is
        // the front's (one value per point), as the renderers read it.
        const bool counted =
            !d.back && (count == Count::all || (count == Count::direct && !d.via_specular));
        if (counted) received[d.patch] += d.incident;
        (d.back ? unsent_back : unsent)[d.patch] += r * d.incident;
        for (size_t g = 0; g < groups; ++g) {
          const dvec3 part = d.incident * share[g];
          if (counted) group_received[g][d.patch] += part;
          (d.back ? group_unsent_back : group_unsent)[g][d.patch] += r * part;
        }
        total_unsent += r * d.incident;
        absorbed += (1.0 - r) * d.incident;
        if (touched_in_merge[d.patch] != merges) {
          touched_in_merge[d.patch] = merges;
          touched.push_back(d.patch);
        }
      }
    }
    // The queue's order is total (power, then id), so update order does not matter.
    for (uint32_t p : touched) queue.update(p, channel_sum(unsent[p] + unsent_back[p]));
    ++merges;
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
    store_energy_stats(all_unsent(), reference, absorbed, escaped, partial.stats);
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
    // Lights first, every kind (LightSources order: area lights, lamps, the sky). What area
    // lights and lamps deposit is direct (or direct-specular) light, which the viewer / HQ and
    // the illumination maps own: it becomes unsent power but is never counted. The sky is not
    // evaluated at view time: its direct light (first hit diffuse) is counted here as soft
    // light; through mirrors and glass it is pass 1's (caustic maps), so not counted.
    for (size_t i = 0; i < lights.size(); ++i) {
      progress.throw_if_cancelled();
      const dvec3 power(lights.power(i));
      const Count count = lights.kind(i) == LightKind::sky ? Count::direct : Count::none;
      const dvec3 missed_before = missed;
      for (size_t g = 0; g < groups; ++g)
        share[g] = dvec3(int(g) == light_group[i] ? 1.0 : 0.0);
      auto merge_light = [&](Shooter::Shot chunk) { merge(chunk, count); };
      if (lights.kind(i) == LightKind::area) {
        const AreaLight& light = lights.area_light(i);
        shot_source.set(scene.meshes[size_t(light.mesh)], light.triangles, light.triangle_cdf,
                        light.triangle_normals);
        shot_source.two_sided = light.two_sided;
        stats.light_rays += shooter.shoot(rays_for(power), power, params.seed, shot, shot_source,
                                          blocks, pairing, progress, merge_light);
      } else if (channel_sum(power) > 0.0) {
        stats.light_rays +=
            shooter.shoot(rays_for(power), power, params.seed, shot, EmitterSource{&lights, i},
                          blocks, pairing, progress, merge_light);
        // Lamps' and the sky's rays that hit nothing never entered the scene (most of a
        // disk's, around the scene): convergence is judged against what entered.
        reference -= missed - missed_before;
      }
      ++shot;
    }
    // What the lights sent: their power up to the Monte Carlo error of rays whose power varies
    // (a spot's falloff, a sky image), so that the bookkeeping below balances exactly.
    stats.power_emitted = vec3(sent);

    const double log_target = std::log(std::max(params.convergence, 1e-300));
    double reported = -1.0;
    while (true) {
      progress.throw_if_cancelled();
      double fraction = 0.0;
      for (int c = 0; c < 3; ++c)
        if (reference[c] > 0.0) fraction = std::max(fraction, total_unsent[c] / reference[c]);
      if (fraction < params.convergence) {
        stats.converged = true;
        break;
      }
      if (stats.shots >= max_shots || stats.light_rays + stats.rays >= max_rays) break;
      const std::optional<uint32_t> source = queue.top();
      if (!source) break;

      const double converged_part = std::clamp(std::log(fraction) / log_target, 0.0, 1.0);
      if (converged_part - reported >= 0.01) {
        progress.update("radiosity", converged_part);
        reported = converged_part;
      }

      const Patch& patch = patches.patches[*source];
      const Mesh& refined = patches.meshes[patch.mesh].mesh;
      const dvec3 power = unsent[*source], back_power = unsent_back[*source];
      unsent[*source] = unsent_back[*source] = dvec3(0.0);
      queue.update(*source, 0.0);
      total_unsent -= power + back_power;
      patch_normals.clear();
      for (uint32_t t : patch.triangles) patch_normals.push_back(triangle_normals[patch.mesh][t]);
      shot_source.set(refined, patch.triangles, patch.triangle_cdf, patch_normals);
      shot_source.two_sided = false;  // each side's power from its own side
      for (const bool back : {false, true}) {
        if (groups > 0) take_share(back ? group_unsent_back : group_unsent, *source);
        const dvec3 side_power = back ? back_power : power;
        // A side with nothing to send is skipped (one-sided surfaces shoot as before).
        if (!(channel_sum(side_power) > 0.0) && (back || channel_sum(back_power) > 0.0))
          continue;
        shot_source.back = back;
        stats.rays += shooter.shoot(rays_for(side_power), side_power, params.seed, shot,
                                    shot_source, blocks, pairing, progress,
                                    [&](Shooter::Shot chunk) { merge(chunk, Count::all); });
        ++shot;
      }
      shot_source.back = false;
      ++stats.shots;
      if (callbacks.on_partial) send_partial();
    }
  }

  store_energy_stats(all_unsent(), reference, absorbed, escaped, stats);
  dvec3 total_received(0.0);
  for (const dvec3& r : received) total_received += r;
  stats.power_received = vec3(total_received);
  store_vertex_radiance(scene, patches, received, result);
  for (size_t g = 0; g < groups; ++g)
    result.group_vertex_radiance.push_back(mesh_vertex_radiance(scene, patches, group_received[g]));
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
