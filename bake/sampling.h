#pragma once
// Random numbers and the square-to-X maps of the paper's Figure 2.
// Everything is deterministic: a generator is seeded from (seed, stream) so that the
// same work item draws the same numbers whatever thread runs it.

#include <cstdint>

#include <glm/glm.hpp>

namespace lb {

// PCG32 (O'Neill 2014): small state, good statistics, independent streams.
class Rng {
 public:
  explicit Rng(uint64_t seed = 0x853c49e6748fea9bULL, uint64_t stream = 0xda3e39cb94b95bdbULL);
  uint32_t next_u32();
  float next_float();  // uniform in [0, 1)
  glm::vec2 next_2d() { float a = next_float(); return {a, next_float()}; }

 private:
  uint64_t state_ = 0;
  uint64_t inc_ = 0;
};

// Mixes several integers into one well-spread seed (splitmix64 finaliser).
uint64_t hash_seed(uint64_t a, uint64_t b = 0, uint64_t c = 0);

// Shirley-Chiu concentric map: a partitioned square maps to a partitioned disk with zones
// that stay compact (the right-hand disk of Figure 2). u in [0,1]^2 -> unit disk.
glm::vec2 square_to_disk(glm::vec2 u);

// Cosine-weighted hemisphere about +z through the concentric disk (Malley's method).
// pdf = cos(theta) / pi.
glm::vec3 square_to_cosine_hemisphere(glm::vec2 u);

// Uniform point on a triangle from u in [0,1]^2, returned as barycentrics (b1, b2).
glm::vec2 square_to_triangle(glm::vec2 u);

// Stratum (i, j) of an n x m grid over the unit square, jittered by `jitter` in [0,1)^2.
inline glm::vec2 stratified(int i, int j, int n, int m, glm::vec2 jitter) {
  return {(float(i) + jitter.x) / float(n), (float(j) + jitter.y) / float(m)};
}

// An orthonormal basis around unit n (Duff et al. 2017, branchless).
struct Frame {
  glm::vec3 tangent, bitangent, normal;
  explicit Frame(glm::vec3 n);
  glm::vec3 to_world(glm::vec3 local) const {
    return tangent * local.x + bitangent * local.y + normal * local.z;
  }
  glm::vec3 to_local(glm::vec3 world) const {
    return {glm::dot(world, tangent), glm::dot(world, bitangent), glm::dot(world, normal)};
  }
};

}  // namespace lb
