#include "bake/transport/eq2_sweep.h"

#include <cstdint>
#include <cstring>

namespace lb {

namespace {

// N floats (ints) in one vector; an alias template would drop the attribute.
template <int N>
struct Vec {
  typedef float Floats __attribute__((vector_size(4 * N)));
  typedef int32_t Ints __attribute__((vector_size(4 * N)));
};
template <int N>
using Floats = typename Vec<N>::Floats;
template <int N>
using Ints = typename Vec<N>::Ints;

// (By reference: a function returning a 32-byte vector has another ABI with AVX than without.)
template <typename T>
[[gnu::always_inline]] inline void load(T& v, const float* p) {
  std::memcpy(&v, p, sizeof(T));
}

// One light, scalar: the formula each lane of the vector loop follows, operation for operation
// (std::max(a, b) is a < b ? b : a, std::min(a, b) is b < a ? b : a).
inline float weight(const Eq2Lights& l, const Eq2Receiver& x, size_t j) {
  const float vx = l.cx[j] - x.px, vy = l.cy[j] - x.py, vz = l.cz[j] - x.pz;
  const float d2 = vx * vx + vy * vy + vz * vz;
  const float facing = -(l.nx[j] * vx + l.ny[j] * vy + l.nz[j] * vz);  // d cos_y
  const float above = x.gx * vx + x.gy * vy + x.gz * vz + l.radius[j];
  const float dot = x.sx * vx + x.sy * vy + x.sz * vz;
  const float cos_x_d = dot < 0.0f ? 0.0f : dot;  // d cos_x
  const float d2_clamped = d2 < l.min_d2[j] ? l.min_d2[j] : d2;
  const float w = l.lum_area[j] * cos_x_d * facing / (d2 * d2_clamped);
  return (facing < above ? facing : above) > 0.0f ? w : -1.0f;
}

// N lanes a step (N a multiple of 4); inlined into each instruction set's entry point below.
template <int N>
[[gnu::always_inline]] inline void sweep(const Eq2Lights& l, const Eq2Receiver& x, float* out,
                                         float partial[4], int& reachable) {
  using F = Floats<N>;
  using F4 = Floats<4>;
  using I4 = Ints<4>;
  const F zero = F{} + 0.0f, minus_one = F{} - 1.0f;
  F4 sums = F4{} + 0.0f;
  I4 counts = I4{} + 0;
  const size_t vector_end = l.count / N * N;
  for (size_t j = 0; j < vector_end; j += N) {
    F cx, cy, cz, nx, ny, nz, radius, lum_area, min_d2;
    load(cx, l.cx + j), load(cy, l.cy + j), load(cz, l.cz + j);
    load(nx, l.nx + j), load(ny, l.ny + j), load(nz, l.nz + j);
    load(radius, l.radius + j), load(lum_area, l.lum_area + j), load(min_d2, l.min_d2 + j);
    const F vx = cx - x.px, vy = cy - x.py, vz = cz - x.pz;
    const F d2 = vx * vx + vy * vy + vz * vz;
    const F facing = -(nx * vx + ny * vy + nz * vz);
    const F above = x.gx * vx + x.gy * vy + x.gz * vz + radius;
    const F dot = x.sx * vx + x.sy * vy + x.sz * vz;
    const F cos_x_d = dot < zero ? zero : dot;
    const F d2_clamped = d2 < min_d2 ? min_d2 : d2;
    const F w = lum_area * cos_x_d * facing / (d2 * d2_clamped);
    const F weights = (facing < above ? facing : above) > zero ? w : minus_one;
    std::memcpy(out + j, &weights, sizeof(F));
    // The sums four lanes at a time, in increasing j: lane k of `sums` is partial[k].
    for (int h = 0; h < N / 4; ++h) {
      F4 q;  // taken from the register, not reloaded from `out`
      std::memcpy(&q, reinterpret_cast<const char*>(&weights) + 16 * h, sizeof(F4));
      const F4 zero4 = F4{} + 0.0f;
      sums += q < zero4 ? zero4 : q;
      counts -= q >= zero4;  // a true lane is -1
    }
  }
  for (size_t j = vector_end; j < l.count; ++j) out[j] = weight(l, x, j);
  for (int k = 0; k < 4; ++k) partial[k] = sums[k];
  int reached = counts[0] + counts[1] + counts[2] + counts[3];
  size_t j = vector_end;
  for (; j + 4 <= l.count; j += 4)
    for (size_t k = 0; k < 4; ++k) {
      partial[k] += out[j + k] < 0.0f ? 0.0f : out[j + k];
      reached += out[j + k] >= 0.0f ? 1 : 0;
    }
  for (; j < l.count; ++j) {
    partial[0] += out[j] < 0.0f ? 0.0f : out[j];
    reached += out[j] >= 0.0f ? 1 : 0;
  }
  reachable = reached;
}

// terms[j] = double(max(w[j], 0)) * scale + uniform, four lights a step.
[[gnu::always_inline]] inline void terms(const float* w, size_t count, double scale,
                                         double uniform, double* out) {
  using F4 = Floats<4>;
  typedef double D4 __attribute__((vector_size(32)));
  const F4 zero = F4{} + 0.0f;
  size_t j = 0;
  for (; j + 4 <= count; j += 4) {
    F4 v;
    load(v, w + j);
    const F4 clamped = v < zero ? zero : v;
    const D4 t = __builtin_convertvector(clamped, D4) * scale + uniform;
    std::memcpy(out + j, &t, sizeof(D4));
  }
  for (; j < count; ++j) out[j] = double(w[j] < 0.0f ? 0.0f : w[j]) * scale + uniform;
}

#if defined(__GNUC__) && defined(__x86_64__)
[[gnu::target("avx2")]] void terms_avx2(const float* w, size_t count, double scale,
                                        double uniform, double* out) {
  terms(w, count, scale, uniform, out);
}

[[gnu::target("avx2")]] void sweep_avx2(const Eq2Lights& l, const Eq2Receiver& x, float* out,
                                        float partial[4], int& reachable) {
  sweep<8>(l, x, out, partial, reachable);
}

bool has_avx2() {
  static const bool yes = __builtin_cpu_supports("avx2");
  return yes;
}
#endif

}  // namespace

void eq2_sweep(const Eq2Lights& lights, const Eq2Receiver& x, float* out, float partial[4],
               int& reachable, bool widest) {
#if defined(__GNUC__) && defined(__x86_64__)
  if (widest && has_avx2()) return sweep_avx2(lights, x, out, partial, reachable);
#endif
  (void)widest;
  sweep<4>(lights, x, out, partial, reachable);
}

void choice_terms(const float* weights, size_t count, double scale, double uniform,
                  double* terms_out, bool widest) {
#if defined(__GNUC__) && defined(__x86_64__)
  if (widest && has_avx2()) return terms_avx2(weights, count, scale, uniform, terms_out);
#endif
  (void)widest;
  terms(weights, count, scale, uniform, terms_out);
}

}  // namespace lb
