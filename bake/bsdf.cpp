#include "bake/bsdf.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "bake/sampling.h"

namespace lb {

vec3 reflect(vec3 incident, vec3 normal) {
  return incident - 2.0f * glm::dot(incident, normal) * normal;
}

std::optional<vec3> refract(vec3 incident, vec3 normal, float eta) {
  const float cos_i = -glm::dot(incident, normal);
  const float sin2_t = eta * eta * std::max(0.0f, 1.0f - cos_i * cos_i);
  if (sin2_t >= 1.0f) return std::nullopt;
  const float cos_t = std::sqrt(1.0f - sin2_t);
  return glm::normalize(eta * incident + (eta * cos_i - cos_t) * normal);
}

float fresnel_dielectric(float cos_incident, float eta) {
  cos_incident = std::clamp(cos_incident, 0.0f, 1.0f);
  const float sin2_t = eta * eta * (1.0f - cos_incident * cos_incident);
  if (sin2_t >= 1.0f) return 1.0f;
  const float cos_t = std::sqrt(1.0f - sin2_t);
  // eta = n1/n2, so rs = (n1 cos_i - n2 cos_t)/(...) = (eta cos_i - cos_t)/(eta cos_i + cos_t).
  const float rs = (eta * cos_incident - cos_t) / (eta * cos_incident + cos_t);
  const float rp = (cos_incident - eta * cos_t) / (cos_incident + eta * cos_t);
  return 0.5f * (rs * rs + rp * rp);
}

// Smith's masking term for GGX, one direction.
static float smith_g1(float cos_theta, float alpha) {
  const float c2 = cos_theta * cos_theta;
  const float tan2 = std::max(0.0f, 1.0f - c2) / std::max(c2, 1e-12f);
  return 2.0f / (1.0f + std::sqrt(1.0f + alpha * alpha * tan2));
}

static std::optional<SpecularScatter> scatter_glossy(const Material& material, vec3 incident,
                                                     vec3 normal, vec2 u) {
  const vec3 n = glm::dot(incident, normal) < 0.0f ? normal : -normal;
  const float alpha = std::max(material.roughness * material.roughness, 1e-4f);
  // Sample h from D(h) cos(theta_h): tan^2(theta_h) = alpha^2 u / (1 - u).
  const float tan2 = alpha * alpha * u.x / std::max(1.0f - u.x, 1e-7f);
  const float cos_h = 1.0f / std::sqrt(1.0f + tan2);
  const float sin_h = std::sqrt(std::max(0.0f, 1.0f - cos_h * cos_h));
  const float phi = 2.0f * std::numbers::pi_v<float> * u.y;
  const vec3 h = Frame(n).to_world({sin_h * std::cos(phi), sin_h * std::sin(phi), cos_h});

  const vec3 outgoing = reflect(incident, h);
  const float cos_i = -glm::dot(incident, n);
  const float cos_o = glm::dot(outgoing, n);
  const float i_dot_h = -glm::dot(incident, h);
  if (cos_o <= 0.0f || cos_i <= 0.0f || i_dot_h <= 0.0f) return std::nullopt;
  const float g = smith_g1(cos_i, alpha) * smith_g1(cos_o, alpha);
  SpecularScatter s;
  s.direction = outgoing;
  s.weight = material.reflectance * (g * i_dot_h / (cos_i * cos_h));
  return s;
}

std::optional<SpecularScatter> scatter_specular(const Material& material, vec3 incident,
                                                vec3 normal, vec2 u) {
  switch (material.kind) {
    case MaterialKind::mirror: {
      SpecularScatter s;
      s.direction = glm::normalize(reflect(incident, normal));
      s.weight = material.reflectance;
      return s;
    }
    case MaterialKind::glass: {
      const bool entering = glm::dot(incident, normal) < 0.0f;
      const vec3 n = entering ? normal : -normal;
      const float eta = entering ? 1.0f / material.ior : material.ior;
      const float f = fresnel_dielectric(-glm::dot(incident, n), eta);
      SpecularScatter s;
      if (u.x < f) {
        s.direction = glm::normalize(reflect(incident, n));
        s.weight = vec3(1.0f);
        return s;
      }
      const auto refracted = refract(incident, n, eta);
      if (!refracted) {  // f == 1 at total internal reflection, so this is only rounding
        s.direction = glm::normalize(reflect(incident, n));
        s.weight = vec3(1.0f);
        return s;
      }
      s.direction = *refracted;
      s.weight = material.reflectance;
      s.transmitted = true;
      return s;
    }
    case MaterialKind::glossy:
      return scatter_glossy(material, incident, normal, u);
    case MaterialKind::diffuse:
      break;
  }
  return std::nullopt;
}

float glossy_albedo(float roughness, float cos_view) {
  constexpr int kSide = 128;
  Material glossy;
  glossy.kind = MaterialKind::glossy;
  glossy.roughness = roughness;
  glossy.reflectance = vec3(1.0f);
  const float c = std::clamp(cos_view, 1e-3f, 1.0f);
  const vec3 incident(std::sqrt(1.0f - c * c), 0.0f, -c);  // onto the plane z = 0 from above
  double sum = 0.0;
  for (int j = 0; j < kSide; ++j)
    for (int i = 0; i < kSide; ++i) {
      const vec2 u((float(i) + 0.5f) / kSide, (float(j) + 0.5f) / kSide);
      if (const auto s = scatter_glossy(glossy, incident, vec3(0.0f, 0.0f, 1.0f), u))
        sum += double(s->weight.x);
    }
  return float(sum / double(kSide * kSide));
}

}  // namespace lb
