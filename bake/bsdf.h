#pragma once
// How light leaves the non-diffuse materials: mirror, glass and glossy metal.
// Directions are directions of travel: `incident` points into the surface, the result
// points away from it. All three passes and the HQ renderer scatter through these.

#include <optional>

#include "bake/scene.h"

namespace lb {

vec3 reflect(vec3 incident, vec3 normal);

// Snell refraction of `incident` through a surface whose normal faces the incident side,
// with eta = n_incident / n_transmitted; nullopt on total internal reflection.
std::optional<vec3> refract(vec3 incident, vec3 normal, float eta);

// Unpolarised Fresnel reflectance of a dielectric; cos_incident in [0,1] on the incident
// side, eta = n_incident / n_transmitted.
float fresnel_dielectric(float cos_incident, float eta);

struct SpecularScatter {
  vec3 direction{0.0f};  // unit, direction of travel after the bounce
  vec3 weight{0.0f};     // throughput multiplier for power or radiance
  bool transmitted = false;
};

// One stochastic bounce off a specular material (mirror, glass, glossy). `normal` is the
// geometric (or shading) normal of the front side; `u` a stratified pair in [0,1)^2.
//  - mirror: reflect, weight = reflectance.
//  - glass: reflect with probability F (weight 1), else refract (weight = transmittance);
//    the choice by F makes the estimator unbiased with weights <= 1. Entering or leaving is
//    decided by the side the ray arrives from.
//  - glossy: GGX microfacet reflection with alpha = roughness^2, microfacet normal sampled
//    from D(h) cos(theta_h); weight = reflectance * G * (i.h) / ((i.n)(h.n)).
//    Returns nullopt when the sampled direction goes below the surface (energy lost, as in
//    any single-scattering microfacet model).
std::optional<SpecularScatter> scatter_specular(const Material& material, vec3 incident,
                                                vec3 normal, vec2 u);

// The glossy lobe's directional albedo: the mean weight of scatter_specular for a glossy
// material of this roughness and reflectance 1, seen at cos_view (what its masking and the
// directions lost below the surface leave), by a 128 x 128 midpoint quadrature of `u`.
// Deterministic; the viewer scales its blurred reflection by it, so raster and HQ agree.
float glossy_albedo(float roughness, float cos_view);

}  // namespace lb
