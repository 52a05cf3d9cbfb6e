#pragma once
// The ray tracing backend: an Embree BVH over the scene's triangles, built once.
// accel.cpp is the only file that includes Embree's headers.

#include <cstdint>
#include <memory>
#include <optional>

#include "bake/scene.h"

namespace lb {

struct Ray {
  vec3 origin;
  vec3 direction;  // need not be unit; t is measured in units of |direction|
  float tmin = 0.0f;
  float tmax = 1e30f;
};

struct Hit {
  float t = 0.0f;
  uint32_t mesh = 0;
  uint32_t triangle = 0;
  vec2 barycentric{0.0f};  // (b1, b2): p = (1-b1-b2) v0 + b1 v1 + b2 v2
  vec3 geometric_normal{0.0f};  // unit, from the triangle's winding (front side)
};

class Accel {
 public:
  explicit Accel(const Scene& scene);  // throws std::runtime_error on Embree failure
  ~Accel();
  Accel(const Accel&) = delete;
  Accel& operator=(const Accel&) = delete;

  std::optional<Hit> intersect(const Ray& ray) const;
  bool occluded(const Ray& ray) const;

  // The yardstick for benchmarks: bare rtcIntersect1 over `rays`, nothing else; returns
  // how many hit. Passes are measured against this on the same scene in the same run.
  size_t intersect_raw(const Ray* rays, size_t count) const;

  // `count` rays at once through Embree's stream API (rtcIntersect1M): hits[i] is rays[i]'s
  // closest hit, the bits intersect() finds, except that exact ties (a shared edge, coincident
  // faces) may go to the other triangle. `coherent` says the rays are close in origin and
  // direction (one light's rays through one small zone), so Embree traces them as packets,
  // which pays even for the specular bounces of such rays; for scattered rays pass false.
  void intersect_many(const Ray* rays, size_t count, std::optional<Hit>* hits, bool coherent) const;
  // The yardstick for intersect_many: bare rtcIntersect1M over `rays` in the same chunks;
  // returns how many hit.
  size_t intersect_raw_many(const Ray* rays, size_t count, bool coherent) const;
  // `count` visibility tests at once through the stream API (rtcOccluded1M): blocked[i] is
  // what occluded(rays[i]) returns. `coherent` as for intersect_many.
  void occluded_many(const Ray* rays, size_t count, bool* blocked, bool coherent) const;
  // The same over rays[order[0]], rays[order[1]], ...: blocked[i] is rays[order[i]]'s. Rays
  // sorted into the caller's order without copying them first (they are copied into Embree's
  // layout anyway).
  void occluded_many(const Ray* rays, const uint32_t* order, size_t count, bool* blocked,
                     bool coherent) const;

  const Scene& scene() const { return scene_; }
  // Length of the scene's bounding-box diagonal, metres, for scale-aware epsilons.
  float scene_scale() const { return scene_scale_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  const Scene& scene_;
  float scene_scale_ = 1.0f;
};

// Moves a ray origin off the surface along the geometric normal, to the side `direction`
// leaves towards. The offset scales with the magnitude of the point's coordinates (floating
// point error grows with them), so it works at any scene scale.
vec3 offset_ray_origin(vec3 point, vec3 geometric_normal, vec3 direction);

// A ray from `from` to `to` whose ends are pulled in by the same scale-aware epsilon,
// for visibility tests between two surface points.
Ray segment_ray(vec3 from, vec3 from_normal, vec3 to, vec3 to_normal);
// The same, written into `ray` field by field: a hot loop that stores the ray into a buffer
// avoids copying a just-built temporary (a store-forwarding stall per ray).
void segment_ray(vec3 from, vec3 from_normal, vec3 to, vec3 to_normal, Ray& ray);

}  // namespace lb
