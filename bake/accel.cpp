#include "bake/accel.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <deque>
#include <stdexcept>
#include <string>

#include <embree3/rtcore.h>

#include "bake/sampling.h"
#include "bake/surface.h"

namespace lb {

namespace {

// A mesh whose material has alpha (glTF MASK or BLEND): what its filter needs per hit.
struct AlphaMask {
  const Mesh* mesh = nullptr;
  const Texture* texture = nullptr;  // null: alpha_factor alone
  float factor = 1.0f;
  float cutoff = 0.5f;
  bool blend = false;  // BLEND: a hit counts with probability alpha (no cutoff)

  float alpha(unsigned triangle, float b1, float b2) const {
    float alpha = factor;
    if (texture && !mesh->uvs.empty()) {
      const uvec3 t = mesh->triangles[triangle];
      const vec2 uv =
          (1.0f - b1 - b2) * mesh->uvs[t.x] + b1 * mesh->uvs[t.y] + b2 * mesh->uvs[t.z];
      alpha *= sample_texture(*texture, uv).x;
    }
    return alpha;
  }
};

// Uniform in [0, 1), a hash of the ray and where it hits: the same ray through the same point
// always gets the same answer (the same bits whatever the thread count), other rays
// independent ones.
float hit_hash(const RTCFilterFunctionNArguments* args, unsigned i) {
  const auto bits = [](float f) { return uint64_t(std::bit_cast<uint32_t>(f)); };
  const unsigned n = args->N;
  const uint64_t origin = bits(RTCRayN_org_x(args->ray, n, i)) |
                          bits(RTCRayN_org_y(args->ray, n, i)) << 32;
  const uint64_t direction = bits(RTCRayN_dir_x(args->ray, n, i)) |
                             bits(RTCRayN_dir_y(args->ray, n, i)) << 32;
  const uint64_t rest = bits(RTCRayN_org_z(args->ray, n, i)) |
                        bits(RTCRayN_dir_z(args->ray, n, i)) << 32;
  const uint64_t hit = uint64_t(RTCHitN_primID(args->hit, n, i)) |
                       bits(RTCHitN_u(args->hit, n, i)) << 32;
  return float(hash_seed(origin, direction, rest ^ mix64(hit)) >> 40) * 0x1p-24f;
}

// Embree's intersection and occlusion filter, for every ray (intersect, occluded, single and
// streamed), so every pass sees through the same surface: MASK, a hit on a cut-out texel is
// no hit; BLEND (stochastic transparency), a hit is no hit with probability 1 - alpha, so on
// average 1 - alpha of the light passes (uncoloured).
void alpha_filter(const RTCFilterFunctionNArguments* args) {
  const auto* mask = static_cast<const AlphaMask*>(args->geometryUserPtr);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    const float alpha = mask->alpha(RTCHitN_primID(args->hit, args->N, i),
                                    RTCHitN_u(args->hit, args->N, i),
                                    RTCHitN_v(args->hit, args->N, i));
    if (mask->blend ? hit_hash(args, i) >= alpha : alpha < mask->cutoff) args->valid[i] = 0;
  }
}

}  // namespace

struct Accel::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::deque<AlphaMask> masks;  // stable addresses: Embree holds pointers to them
  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

static void throw_on_embree_error(RTCDevice device, const char* what) {
  const RTCError error = rtcGetDeviceError(device);
  if (error != RTC_ERROR_NONE)
    throw std::runtime_error(std::string("Embree: ") + what + " failed (error " +
                             std::to_string(int(error)) + ")");
}

Accel::Accel(const Scene& scene) : impl_(std::make_unique<Impl>()), scene_(scene) {
  impl_->device = rtcNewDevice(nullptr);
  if (!impl_->device) throw std::runtime_error("Embree: cannot create a device");
  impl_->scene = rtcNewScene(impl_->device);
  // Robust traversal: no missed hits along shared edges, which would leak light.
  rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);

  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    if (mesh.triangles.empty() || mesh.positions.empty()) continue;
    RTCGeometry geometry = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    // Embree-owned buffers come padded for its 16-byte vertex loads.
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float),
        mesh.positions.size()));
    auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned),
        mesh.triangles.size()));
    throw_on_embree_error(impl_->device, "allocating geometry buffers");
    for (size_t i = 0; i < mesh.positions.size(); ++i)
      for (int k = 0; k < 3; ++k) vertices[3 * i + size_t(k)] = mesh.positions[i][k];
    for (size_t i = 0; i < mesh.triangles.size(); ++i)
      for (int k = 0; k < 3; ++k) indices[3 * i + size_t(k)] = mesh.triangles[i][k];
    const Material& material = scene.materials[size_t(mesh.material)];
    // Only meshes with alpha get a filter: the rest trace as before.
    if (material.alpha_mask || material.alpha_blend) {
      AlphaMask& mask = impl_->masks.emplace_back();
      mask.mesh = &mesh;
      mask.texture = material.alpha_texture >= 0
                         ? &scene.textures[size_t(material.alpha_texture)]
                         : nullptr;
      mask.factor = material.alpha_factor;
      mask.cutoff = material.alpha_cutoff;
      mask.blend = material.alpha_blend;
      rtcSetGeometryUserData(geometry, &mask);
      rtcSetGeometryIntersectFilterFunction(geometry, alpha_filter);
      rtcSetGeometryOccludedFilterFunction(geometry, alpha_filter);
    }
    rtcCommitGeometry(geometry);
    rtcAttachGeometryByID(impl_->scene, geometry, unsigned(m));
    rtcReleaseGeometry(geometry);
  }
  rtcCommitScene(impl_->scene);
  throw_on_embree_error(impl_->device, "building the BVH");

  const Bounds bounds = scene_bounds(scene);
  scene_scale_ = bounds.empty() ? 1.0f : std::max(bounds.diagonal(), 1e-6f);
}

Accel::~Accel() = default;

// Fills `r` in place, field by field: building a temporary RTCRay and copying it costs a
// store-forwarding stall per ray (wide loads of freshly written narrow stores).
static void to_embree(const Ray& ray, RTCRay& r) {
  r.org_x = ray.origin.x;
  r.org_y = ray.origin.y;
  r.org_z = ray.origin.z;
  r.tnear = ray.tmin;
  r.dir_x = ray.direction.x;
  r.dir_y = ray.direction.y;
  r.dir_z = ray.direction.z;
  r.time = 0.0f;
  r.tfar = ray.tmax;
  r.mask = 0xFFFFFFFFu;
  r.id = 0;
  r.flags = 0;
}

static void to_embree(const Ray& ray, RTCRayHit& rayhit) {
  to_embree(ray, rayhit.ray);
  rayhit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rayhit.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}

// Embree's Ng faces our counter-clockwise front but is not normalised; reading it is much
// cheaper than refetching the triangle (test_accel checks the orientation).
static void to_hit(const RTCRayHit& rayhit, Hit& hit) {
  hit.t = rayhit.ray.tfar;
  hit.mesh = rayhit.hit.geomID;
  hit.triangle = rayhit.hit.primID;
  hit.barycentric = {rayhit.hit.u, rayhit.hit.v};
  hit.geometric_normal = glm::normalize(vec3(rayhit.hit.Ng_x, rayhit.hit.Ng_y, rayhit.hit.Ng_z));
}

std::optional<Hit> Accel::intersect(const Ray& ray) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rayhit;
  to_embree(ray, rayhit);
  rtcIntersect1(impl_->scene, &context, &rayhit);
  if (rayhit.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
  std::optional<Hit> hit(std::in_place);
  to_hit(rayhit, *hit);
  return hit;
}

bool Accel::occluded(const Ray& ray) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay r;
  to_embree(ray, r);
  rtcOccluded1(impl_->scene, &context, &r);
  return r.tfar < 0.0f;  // Embree sets tfar to -inf when something blocks the ray
}

size_t Accel::intersect_raw(const Ray* rays, size_t count) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  size_t hits = 0;
  for (size_t i = 0; i < count; ++i) {
    RTCRayHit rayhit;
    to_embree(rays[i], rayhit);
    rtcIntersect1(impl_->scene, &context, &rayhit);
    hits += rayhit.hit.geomID != RTC_INVALID_GEOMETRY_ID;
  }
  return hits;
}

// Rays go to Embree in chunks small enough for the stack; a chunk is several packets.
constexpr size_t stream_chunk = 64;

static RTCIntersectContext stream_context(bool coherent) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags =
      coherent ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
  return context;
}

void Accel::intersect_many(const Ray* rays, size_t count, std::optional<Hit>* hits,
                           bool coherent) const {
  RTCIntersectContext context = stream_context(coherent);
  RTCRayHit batch[stream_chunk];
  for (size_t first = 0; first < count; first += stream_chunk) {
    const unsigned n = unsigned(std::min(stream_chunk, count - first));
    for (unsigned i = 0; i < n; ++i) to_embree(rays[first + i], batch[i]);
    rtcIntersect1M(impl_->scene, &context, batch, n, sizeof(RTCRayHit));
    for (unsigned i = 0; i < n; ++i) {
      if (batch[i].hit.geomID == RTC_INVALID_GEOMETRY_ID)
        hits[first + i].reset();
      else
        to_hit(batch[i], hits[first + i].emplace());
    }
  }
}

size_t Accel::intersect_raw_many(const Ray* rays, size_t count, bool coherent) const {
  RTCIntersectContext context = stream_context(coherent);
  RTCRayHit batch[stream_chunk];
  size_t hits = 0;
  for (size_t first = 0; first < count; first += stream_chunk) {
    const unsigned n = unsigned(std::min(stream_chunk, count - first));
    for (unsigned i = 0; i < n; ++i) to_embree(rays[first + i], batch[i]);
    rtcIntersect1M(impl_->scene, &context, batch, n, sizeof(RTCRayHit));
    for (unsigned i = 0; i < n; ++i) hits += batch[i].hit.geomID != RTC_INVALID_GEOMETRY_ID;
  }
  return hits;
}

// Shadow rays ray(0) .. ray(count - 1) through rtcOccluded1M in chunks; blocked[i] is ray(i)'s.
template <class RayAt>
static void occluded_stream(RTCScene scene, bool coherent, size_t count, const RayAt& ray,
                            bool* blocked) {
  RTCIntersectContext context = stream_context(coherent);
  RTCRay batch[stream_chunk];
  for (size_t first = 0; first < count; first += stream_chunk) {
    const unsigned n = unsigned(std::min(stream_chunk, count - first));
    for (unsigned i = 0; i < n; ++i) to_embree(ray(first + i), batch[i]);
    rtcOccluded1M(scene, &context, batch, n, sizeof(RTCRay));
    for (unsigned i = 0; i < n; ++i) blocked[first + i] = batch[i].tfar < 0.0f;
  }
}

void Accel::occluded_many(const Ray* rays, size_t count, bool* blocked, bool coherent) const {
  occluded_stream(impl_->scene, coherent, count, [&](size_t i) -> const Ray& { return rays[i]; },
                  blocked);
}

void Accel::occluded_many(const Ray* rays, const uint32_t* order, size_t count, bool* blocked,
                          bool coherent) const {
  occluded_stream(impl_->scene, coherent, count,
                  [&](size_t i) -> const Ray& { return rays[order[i]]; }, blocked);
}

// After Waechter and Binder, "A Fast and Robust Method for Avoiding Self-Intersection"
// (Ray Tracing Gems, 2019): move the point a fixed number of ULPs along the normal, so the
// offset grows with the coordinates' magnitude; near the origin, where ULPs vanish, use a
// small absolute offset instead.
vec3 offset_ray_origin(vec3 point, vec3 geometric_normal, vec3 direction) {
  constexpr float near_origin = 1.0f / 32.0f;
  constexpr float absolute_scale = 1.0f / 65536.0f;
  constexpr float ulp_scale = 256.0f;
  const vec3 n = glm::dot(geometric_normal, direction) < 0.0f ? -geometric_normal
                                                                : geometric_normal;
  vec3 result;
  for (int k = 0; k < 3; ++k) {
    const int ulps = int(ulp_scale * n[k]);
    const int bits = std::bit_cast<int>(point[k]) + (point[k] < 0.0f ? -ulps : ulps);
    result[k] = std::abs(point[k]) < near_origin ? point[k] + absolute_scale * n[k]
                                                 : std::bit_cast<float>(bits);
  }
  return result;
}

Ray segment_ray(vec3 from, vec3 from_normal, vec3 to, vec3 to_normal) {
  Ray ray;
  segment_ray(from, from_normal, to, to_normal, ray);
  return ray;
}

void segment_ray(vec3 from, vec3 from_normal, vec3 to, vec3 to_normal, Ray& ray) {
  const vec3 origin = offset_ray_origin(from, from_normal, to - from);
  const vec3 target = offset_ray_origin(to, to_normal, from - to);
  ray.origin = origin;
  ray.direction = target - origin;
  ray.tmin = 0.0f;
  ray.tmax = 1.0f;
}

}  // namespace lb
