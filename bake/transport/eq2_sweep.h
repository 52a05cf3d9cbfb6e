#pragma once
// The per-light loops of DirectLight's light choice: Eq. 2 at every planar light's centre for
// one receiver (DirectLight::eq2_weights, which documents the formula) and the choice's
// probabilities from those weights. They run once per pixel over every light, so they are what
// grows with the light count.
//
// Written with explicit SIMD (GCC vector extensions): 8 lanes where the CPU has AVX2, 4 (SSE2)
// elsewhere. Each lane does the scalar formula's float operations in its order, and the sums
// keep their order (below), so the weights and the sum have the same bits on any CPU and at
// any lane count.

#include <cstddef>

namespace lb {

// The planar lights, structure of arrays, `count` entries each (DirectLight's members).
struct Eq2Lights {
  const float* cx;
  const float* cy;
  const float* cz;  // centroid
  const float* nx;
  const float* ny;
  const float* nz;  // mean normal
  const float* radius;
  const float* lum_area;
  const float* min_d2;
  size_t count = 0;
};

// The receiver: position p, geometric normal g, shading normal s.
struct Eq2Receiver {
  float px, py, pz, gx, gy, gz, sx, sy, sz;
};

// out[j] = light j's Eq. 2 weight at the receiver, -1 where it cannot reach it (j < count).
// Also partial[k] = the sum of max(out[j], 0) over j = k mod 4, j < count / 4 * 4, in
// increasing j (the rest, j >= count / 4 * 4, added to partial[0] after), and `reachable` =
// the number of out[j] >= 0: DirectLight's four partial sums when these are all its lights.
// `widest` false keeps to 4 lanes (tests compare the two widths).
void eq2_sweep(const Eq2Lights& lights, const Eq2Receiver& x, float* out, float partial[4],
               int& reachable, bool widest = true);

// terms[j] = double(max(weights[j], 0)) * scale + uniform for j < count: the choice's p_j
// (DirectLight::prepare_choice), each as the scalar expression rounds it.
void choice_terms(const float* weights, size_t count, double scale, double uniform,
                  double* terms, bool widest = true);

}  // namespace lb
