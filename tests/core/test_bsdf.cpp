#include <cmath>

#include <gtest/gtest.h>

#include "bake/bsdf.h"
#include "bake/sampling.h"

namespace lb {
namespace {

TEST(Fresnel, MatchesKnownValues) {
  // Normal incidence: ((n1-n2)/(n1+n2))^2 = 0.04 for glass of index 1.5.
  EXPECT_NEAR(fresnel_dielectric(1.0f, 1.0f / 1.5f), 0.04f, 1e-6f);
  EXPECT_NEAR(fresnel_dielectric(1.0f, 1.5f), 0.04f, 1e-6f);
  // Grazing incidence reflects everything.
  EXPECT_NEAR(fresnel_dielectric(0.0f, 1.0f / 1.5f), 1.0f, 1e-6f);
  // Past the critical angle (asin(1/1.5) = 41.8 deg) inside glass: total internal reflection.
  EXPECT_EQ(fresnel_dielectric(std::cos(0.8f), 1.5f), 1.0f);
  // Brewster's angle atan(1.5): p-polarised reflectance vanishes, so F = rs^2 / 2 = 0.0739.
  EXPECT_NEAR(fresnel_dielectric(std::cos(std::atan(1.5f)), 1.0f / 1.5f), 0.0739f, 5e-4f);
}

TEST(Refract, ObeysSnell) {
  const vec3 n(0, 0, 1);
  const float theta_i = 0.6f;
  const vec3 incident(std::sin(theta_i), 0, -std::cos(theta_i));
  const auto t = refract(incident, n, 1.0f / 1.5f);
  ASSERT_TRUE(t);
  EXPECT_NEAR(glm::length(*t), 1.0f, 1e-6f);
  const float sin_t = std::sqrt(t->x * t->x + t->y * t->y);
  EXPECT_NEAR(sin_t * 1.5f, std::sin(theta_i), 1e-5f);
  EXPECT_LT(t->z, 0.0f);
  EXPECT_FALSE(refract(vec3(std::sin(1.2f), 0, -std::cos(1.2f)), n, 1.5f));
}

TEST(ScatterSpecular, GlassConservesEnergyWhenClear) {
  Material glass;
  glass.kind = MaterialKind::glass;
  glass.reflectance = vec3(1.0f);
  glass.ior = 1.5f;
  Rng rng(2);
  const vec3 incident = glm::normalize(vec3(0.3f, 0.1f, -1.0f));
  int reflected = 0;
  const int n = 100000;
  for (int i = 0; i < n; ++i) {
    const auto s = scatter_specular(glass, incident, vec3(0, 0, 1), rng.next_2d());
    ASSERT_TRUE(s);
    EXPECT_FLOAT_EQ(s->weight.x, 1.0f);
    reflected += !s->transmitted;
  }
  const float f = fresnel_dielectric(-incident.z, 1.0f / 1.5f);
  EXPECT_NEAR(double(reflected) / n, f, 4e-3);
}

// Directional albedo of the GGX model (separable Smith G, alpha = roughness^2) by midpoint
// quadrature over the outgoing hemisphere: the reference the sampler must reproduce.
double ggx_albedo_by_quadrature(double alpha, vec3 to_light) {
  auto g1 = [alpha](double c) { return 2.0 / (1.0 + std::sqrt(1.0 + alpha * alpha * (1.0 - c * c) / (c * c))); };
  const int n = 400;
  double sum = 0.0;
  for (int p = 0; p < n; ++p)
    for (int q = 0; q < 4 * n; ++q) {
      const double ct = (p + 0.5) / n, st = std::sqrt(1.0 - ct * ct);
      const double phi = 2.0 * M_PI * (q + 0.5) / (4 * n);
      const glm::dvec3 o(st * std::cos(phi), st * std::sin(phi), ct);
      const glm::dvec3 h = glm::normalize(glm::dvec3(to_light) + o);
      const double c2 = h.z * h.z, t2 = (1.0 - c2) / c2;
      const double d = 1.0 / (M_PI * alpha * alpha * c2 * c2 * std::pow(1.0 + t2 / (alpha * alpha), 2.0));
      const double f = d * g1(to_light.z) * g1(ct) / (4.0 * to_light.z * ct);
      sum += f * ct * (1.0 / n) * (2.0 * M_PI / (4 * n));
    }
  return sum;
}

TEST(ScatterSpecular, GlossyAlbedoMatchesQuadratureAndLobeWidens) {
  const vec3 incident = glm::normalize(vec3(0.5f, 0.0f, -1.0f));
  const vec3 mirror_dir = reflect(incident, vec3(0, 0, 1));
  double spread_prev = 0.0;
  for (float roughness : {0.1f, 0.3f, 0.5f, 0.6f}) {
    Material metal;
    metal.kind = MaterialKind::glossy;
    metal.reflectance = vec3(1.0f);
    metal.roughness = roughness;
    Rng rng(4);
    double weight = 0.0, spread = 0.0;
    const int n = 200000;
    for (int i = 0; i < n; ++i) {
      const auto s = scatter_specular(metal, incident, vec3(0, 0, 1), rng.next_2d());
      if (!s) continue;  // sampled below the horizon: the BRDF is zero there
      EXPECT_GT(s->direction.z, 0.0f);
      weight += s->weight.x;
      spread += 1.0 - glm::dot(s->direction, mirror_dir);
    }
    const double reference = ggx_albedo_by_quadrature(double(roughness) * roughness, -incident);
    EXPECT_NEAR(weight / n, reference, 0.01) << "roughness " << roughness;
    EXPECT_GT(spread / n, spread_prev);
    spread_prev = spread / n;
  }
}

// The table the viewer scales glossy reflections by (lb::glossy_albedo, 128 x 128 points of the
// sampler) against the independent quadrature over outgoing directions: within 0.01 from
// grazing (cos 0.1; worst measured 0.008 there) to head-on; a near-mirror keeps nearly all.
TEST(ScatterSpecular, GlossyAlbedoTableMatchesQuadrature) {
  for (float roughness : {0.15f, 0.3f, 0.5f, 0.8f}) {
    for (float cos_view : {0.1f, 0.3f, 0.6f, 0.95f}) {
      const vec3 to_viewer(std::sqrt(1.0f - cos_view * cos_view), 0.0f, cos_view);
      const double reference = ggx_albedo_by_quadrature(double(roughness) * roughness, to_viewer);
      EXPECT_NEAR(glossy_albedo(roughness, cos_view), reference, 0.01)
          << "roughness " << roughness << ", cos " << cos_view;
    }
  }
  EXPECT_GT(glossy_albedo(0.02f, 0.5f), 0.995f);
}

}  // namespace
}  // namespace lb
