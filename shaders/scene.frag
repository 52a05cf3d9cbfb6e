// The viewer's shading: L = emission + R * (direct + illumination map + vertex radiosity),
// with R the reflectance times its texture (bake/bake_result.h), one accumulator per term and
// a debug output per term (TERM). Specular surfaces show a planar reflection or the
// environment capture.
//
// Features are compile-time defines, not uniforms (the renderer compiles one variant per
// combination it meets and caches it): llvmpipe runs both sides of a branch, so a uniform
// `if` would cost every pixel the whole shader. Defines, all 0 or 1 unless noted:
//   TERM (0..10, common.glsl), USE_DIRECT, USE_SHADOWS, USE_CAUSTICS, USE_RADIOSITY,
//   SPECULAR (mirror, glass, glossy), BUMP_KIND (0 none, 1 height, 2 normal map),
//   HAS_NORMALS, HAS_REFLECTANCE_TEXTURE, HAS_LIGHTMAP, HAS_DIRECTIONAL (the map's L1 band,
//   bake/sh_projection.h, taken at the shading normal), HAS_VERTEX_RADIANCE, HAS_SOFT_MAP
//   (the bake's soft-light texel map replaces the vertex radiosity), HAS_SOFT_DIRECTIONAL (its
//   L1 band, s = 0, on a bumped surface), HAS_PATCHES,
//   HAS_ENVIRONMENT, HAS_PLANAR, HAS_LAMPS (point, spot or directional lamps in the scene),
//   STOCHASTIC (one light per fragment, picked by its contribution: light_pick.glsl),
//   PROBE_LIT (a moving object: its baked light from u_probe_sh, the light probes' radiance SH
//   blended at its centre, bake/probe_grid.h, and with HAS_VERTEX_RADIANCE the probes blended
//   at each vertex, in place of maps and vertex radiosity, shown as the radiosity term; its
//   direct light is drawn as every surface's), ALPHA_CUT (glTF MASK or BLEND: alpha.glsl's
//   cut-outs, the same as the depth pre-pass's).
#include "common.glsl"
#include "lights.glsl"
#include "shadows.glsl"
#include "lamps.glsl"
#include "lamp_shadows.glsl"
#include "light_pick.glsl"
#include "bump.glsl"
#include "alpha.glsl"

in vec3 v_position;
in vec3 v_normal;
in vec2 v_uv;
in vec2 v_lightmap_uv;
in vec4 v_tangent;
in vec3 v_radiance;

uniform vec3 u_camera_position;

// Figure 8 toggles.
uniform vec3 u_ambient;  // constant (Whitted) ambient, E/pi; zero when off

// Material.
uniform int u_kind;
uniform vec3 u_reflectance;
uniform sampler2D u_reflectance_texture;
uniform vec3 u_emission;
uniform bool u_two_sided_emission;  // glTF doubleSided emitters glow on the back too
uniform float u_ior;
uniform float u_roughness;
// A glossy lobe's directional albedo at view cosines (i + 0.5) / 16 (lb::glossy_albedo): its
// masking and the directions lost below the surface, which a blurred reflection alone misses.
uniform float u_glossy_albedo[16];

float glossy_albedo(float cos_view) {
  float x = clamp(cos_view * 16.0 - 0.5, 0.0, 15.0);
  int i = min(int(x), 14);
  return mix(u_glossy_albedo[i], u_glossy_albedo[i + 1], x - float(i));
}

// Baked terms.
uniform sampler2D u_lightmap;
uniform sampler2D u_lightmap_l1_x, u_lightmap_l1_y, u_lightmap_l1_z;  // world axes
uniform sampler2D u_soft_light;
uniform sampler2D u_soft_light_l1_x, u_soft_light_l1_y, u_soft_light_l1_z;  // world axes
uniform usamplerBuffer u_triangle_patch;
uniform int u_first_triangle;  // of this draw in the mesh: culled draws start mid-mesh
uniform vec3 u_probe_sh[9];    // PROBE_LIT: L2 radiance SH, bake/probe_grid.h's order
// A coarser level of detail's error bound (viewer/mesh_detail.h), metres; 0 at full detail.
// Its triangles may lie that far inside the surface the shadow maps hold, so the direct
// light is taken that far out along the normal, or they would shadow themselves.
uniform float u_detail_lift;

// Planar mirrors: the scene drawn mirrored about this mesh's plane, looked up per pixel.
uniform sampler2D u_planar_reflection;
uniform float u_planar_levels;

// rgb: radiance; alpha: the distance from the camera (m), which environment captures keep
// for their parallax correction (shaders/environment.glsl).
out vec4 o_radiance;

// Environment capture for curved mirrors, glass and glossy metal.
#include "environment.glsl"

float fresnel_dielectric(float cos_i, float eta) {
  float sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
  if (sin2_t >= 1.0) return 1.0;
  float cos_t = sqrt(1.0 - sin2_t);
  float rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  float rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  return 0.5 * (rs * rs + rp * rp);
}

vec3 planar_reflection(float roughness) {
  vec2 uv = gl_FragCoord.xy / vec2(textureSize(u_planar_reflection, 0));
  return textureLod(u_planar_reflection, uv, roughness * u_planar_levels).rgb;
}

// Internal reflections a refracted ray follows inside a solid glass object: 2, so a ball shows
// the ceiling light's spot seen through two of them, as HQ and the reference do. Even the 4%
// reflected head-on matter when they see a light (following them only where more than 3% of
// the light stayed inside lost a third of the gain on cornell_glass's ball).
const int kGlassInternalReflections = 2;

// Radiance arriving along the ray that entered glass at `p` along `refracted` (`entering`:
// from outside), times the glass's transmittance (its reflectance, once a refraction, as in HQ
// and the reference: T^2 through a solid, T^4 through a hollow object).
// Solid: at each crossing the Fresnel share leaves, refracted, and the rest reflects inside, up
// to kGlassInternalReflections times; the light still inside after that is taken to leave like
// the exits found, in their proportions (no energy lost: giving it all to the last exit made
// the ball's spot twice too bright, all to the first, as before, missed the spot). Hollow (the
// exited ray meets the object again): through the far wall as a thin slab, the direction kept,
// two refractions more, the light the far wall reflects taken to leave alike too (clear glass
// in a uniform field is then invisible, as it must be). The shared cube finds no crossing and
// reads the entry's ray, as if it left there. Environment searches stay out of branches:
// llvmpipe runs both sides of a branch.
vec3 glass_interior(vec3 p, vec3 refracted, vec3 reflectance, bool entering) {
  vec3 through = reflectance * reflectance;
  vec3 crossing = p, normal = refracted;
  bool solid = entering && glass_crossing(p, refracted, crossing, normal);
  vec3 out_direction = refract(refracted, -normal, u_ior);
  bool leaves = solid && dot(out_direction, out_direction) > 0.0;
  vec3 crossing2, normal2;
  if (leaves &&
      glass_crossing(crossing + 1e-4 * out_direction, out_direction, crossing2, normal2)) {
    through *= reflectance * reflectance;
    crossing = crossing2;
    solid = false;
  } else if (!solid) {
    out_direction = refracted;
  }
  // The first exit; then, in a solid, the internal reflections (a loop whose count is 0 for
  // other glass, which llvmpipe skips for a block whose pixels all have 0).
  bool exits = dot(out_direction, out_direction) > 0.0;
  float inside =
      !solid ? 0.0 : exits ? fresnel_dielectric(dot(normal, refracted), 1.0 / u_ior) : 1.0;
  float left = 1.0 - inside;  // shares of the entering light: left so far, still inside
  // Where no light leaves at all (total internal reflection at every crossing, the rims of thin
  // walls): what the entry's ray sees from the first crossing, as before the reflections.
  vec3 first = environment(crossing, exits ? out_direction : refracted, 0.0);
  vec3 sum = left * first;
  vec3 direction = refracted;
  int reflections = inside > 0.0 ? kGlassInternalReflections : 0;
  for (int k = 0; k < reflections; ++k) {
    direction = reflect(direction, normal);
    if (!glass_crossing(crossing + 1e-4 * direction, direction, crossing, normal)) break;
    out_direction = refract(direction, -normal, u_ior);
    exits = dot(out_direction, out_direction) > 0.0;
    float f = exits ? fresnel_dielectric(dot(normal, direction), 1.0 / u_ior) : 1.0;
    float leaving = inside * (1.0 - f);
    sum += leaving * environment(crossing, exits ? out_direction : direction, 0.0);
    left += leaving;
    inside -= leaving;
  }
  return through * (left > 0.0 ? sum / left : first);
}

vec3 specular_radiance(vec3 p, vec3 n, vec3 view, vec3 reflectance) {
  vec3 reflected = reflect(-view, n);
#if HAS_PLANAR
  if (u_kind == KIND_MIRROR) return reflectance * planar_reflection(0.0);
  if (u_kind == KIND_GLOSSY)
    return reflectance * glossy_albedo(dot(n, view)) * planar_reflection(u_roughness);
#endif
  // Mirrors and glossy metal share one lookup (llvmpipe would run both branches' searches).
  float roughness = u_kind == KIND_GLOSSY ? u_roughness : 0.0;
  if (u_kind != KIND_GLASS) {
    float albedo = u_kind == KIND_GLOSSY ? glossy_albedo(dot(n, view)) : 1.0;
    return reflectance * albedo * environment(p, reflected, roughness);
  }
  // Glass: Fresnel between reflection and refraction (entering or leaving).
  float cos_i = dot(n, view);
  bool entering = cos_i > 0.0;
  float eta = cos_i > 0.0 ? u_ior : 1.0 / u_ior;
  vec3 nn = cos_i > 0.0 ? n : -n;
  cos_i = abs(cos_i);
  float f = fresnel_dielectric(cos_i, eta);
  vec3 refracted = refract(-view, nn, 1.0 / eta);
  vec3 transmitted = dot(refracted, refracted) > 0.0
                         ? glass_interior(p, refracted, reflectance, entering)
                         : vec3(0.0);
  return f * environment(p, reflect(-view, nn), 0.0) + (1.0 - f) * transmitted;
}

// A map's L1 band decoded (bake/sh_projection.h, decode_directional): E(n)/pi = max(0, L0 (1 -
// W (1 - n . n0)) + L1 . n), W = (1 + s) / 2, L1 per world axis, n bumped, n0 not.
vec3 decode_band(vec3 l0, vec3 l1_x, vec3 l1_y, vec3 l1_z, float tilt_weight, vec3 n, vec3 n0) {
  return max(l0 * (1.0 - tilt_weight * (1.0 - dot(n, n0))) + l1_x * n.x + l1_y * n.y + l1_z * n.z,
             vec3(0.0));
}

#if PROBE_LIT
// E(n)/pi = sum_lm A_l c_lm Y_lm(n) / pi (A = pi, 2 pi/3, pi/4), clamped at 0.
vec3 probe_irradiance_over_pi(vec3 n) {
  return max(u_probe_sh[0] * 0.282095 +
                 (2.0 / 3.0) * 0.488603 * (u_probe_sh[1] * n.y + u_probe_sh[2] * n.z +
                                           u_probe_sh[3] * n.x) +
                 0.25 * (1.092548 * (u_probe_sh[4] * n.x * n.y + u_probe_sh[5] * n.y * n.z +
                                     u_probe_sh[7] * n.x * n.z) +
                         0.315392 * u_probe_sh[6] * (3.0 * n.z * n.z - 1.0) +
                         0.546274 * u_probe_sh[8] * (n.x * n.x - n.y * n.y)),
             vec3(0.0));
}
#endif

void main() {
#if ALPHA_CUT
  if (alpha_cut(v_uv, alpha_pixel_key(u_frame))) discard;
#endif
  vec3 p = v_position;
  vec3 ng = normalize(cross(dFdx(p), dFdy(p)));
  vec3 view = normalize(u_camera_position - p);
  // The derivative normal faces the camera; orient it to the triangle's front with the
  // interpolated normal, or with the winding when the mesh has no normals.
#if HAS_NORMALS
  vec3 n_interp = normalize(v_normal);
#else
  if (!gl_FrontFacing) ng = -ng;
  vec3 n_interp = ng;
#endif
  if (dot(ng, n_interp) < 0.0) ng = -ng;
  vec3 p_lit = p;  // where the direct light is taken
  if (u_detail_lift > 0.0) p_lit += ng * u_detail_lift;
#if BUMP_KIND != 0
  vec3 n = bumped_normal(p, v_uv, n_interp, v_tangent);
#else
  vec3 n = n_interp;
#endif

  vec3 reflectance = u_reflectance;
#if HAS_REFLECTANCE_TEXTURE
  reflectance *= texture(u_reflectance_texture, v_uv).rgb;
#endif
  vec3 emission = gl_FrontFacing || u_two_sided_emission ? u_emission : vec3(0.0);

  // ---- the terms, each as incident light E/pi (bake/bake_result.h) ----
  vec3 direct = vec3(0.0), caustic = vec3(0.0), radiosity = vec3(0.0), specular = vec3(0.0);
#if SPECULAR
  specular = specular_radiance(p, n, view, reflectance);
#else
#if USE_DIRECT && STOCHASTIC
  direct = direct_one_light(p_lit, n, ng);
#elif USE_DIRECT
  for (int j = 0; j < u_light_range.y; ++j) {
    int i = listed_light(j);
    vec3 e = light_irradiance_over_pi(i, p_lit, n);
#if USE_SHADOWS
    if (max(e.r, max(e.g, e.b)) > 0.0) e *= light_visibility(i, p_lit, ng);
#endif
    direct += e;
  }
#if HAS_LAMPS
  for (int i = 0; i < u_lamp_count; ++i) {
    float distance_to_lamp;
    vec3 l = lamp_direction_from(i, p_lit, distance_to_lamp);
    vec3 e = lamp_irradiance_over_pi(i, l, distance_to_lamp, n, ng);
#if USE_SHADOWS
    if (max(e.r, max(e.g, e.b)) > 0.0) e *= lamp_visibility(i, p_lit, ng, l, distance_to_lamp);
#endif
    direct += e;
  }
#endif
#endif
#if HAS_LIGHTMAP && USE_CAUSTICS
  caustic = texture(u_lightmap, v_lightmap_uv).rgb;
#if HAS_DIRECTIONAL
  // s, the direct term's share of L0, in the x map's alpha.
  vec4 l1_x = texture(u_lightmap_l1_x, v_lightmap_uv);
  caustic = decode_band(caustic, l1_x.rgb, texture(u_lightmap_l1_y, v_lightmap_uv).rgb,
                        texture(u_lightmap_l1_z, v_lightmap_uv).rgb, 0.5 + 0.5 * l1_x.a, n,
                        n_interp);
#endif
#endif
#if PROBE_LIT && USE_RADIOSITY
  radiosity = probe_irradiance_over_pi(n);
#if HAS_VERTEX_RADIANCE
  // The probes blended at each vertex, at its normal; the centre's blend adds what a bump
  // turns the normal by (nothing on a smooth surface).
  radiosity = max(v_radiance + radiosity - probe_irradiance_over_pi(n_interp), vec3(0.0));
#endif
#elif HAS_SOFT_MAP && USE_RADIOSITY
  radiosity = texture(u_soft_light, v_lightmap_uv).rgb;
#if HAS_SOFT_DIRECTIONAL
  // The soft map's band: s = 0 (W = 1/2), light from the whole hemisphere (soft_band.h).
  radiosity = decode_band(radiosity, texture(u_soft_light_l1_x, v_lightmap_uv).rgb,
                          texture(u_soft_light_l1_y, v_lightmap_uv).rgb,
                          texture(u_soft_light_l1_z, v_lightmap_uv).rgb, 0.5, n, n_interp);
#endif
#elif HAS_VERTEX_RADIANCE && USE_RADIOSITY
  radiosity = v_radiance;
#endif
#endif
  vec3 ambient = SPECULAR != 0 ? vec3(0.0) : u_ambient;

  vec3 result;
#if TERM == TERM_ALL
  result = emission + specular + reflectance * (direct + caustic + radiosity + ambient);
#elif TERM == TERM_DIRECT
  result = reflectance * direct;
#elif TERM == TERM_CAUSTIC
  result = reflectance * caustic;
#elif TERM == TERM_RADIOSITY
  result = reflectance * radiosity;
#elif TERM == TERM_AMBIENT
  result = reflectance * ambient;
#elif TERM == TERM_SPECULAR
  result = specular;
#elif TERM == TERM_BAKED
  result = emission + reflectance * (caustic + radiosity);
#elif TERM == TERM_NORMALS
  result = 0.5 * n + 0.5;
#elif TERM == TERM_TEXEL_DENSITY
  // One checker square per illumination-map texel; grey where a mesh has no map.
#if HAS_LIGHTMAP
  ivec2 texel = ivec2(floor(v_lightmap_uv * vec2(textureSize(u_lightmap, 0))));
  result = ((texel.x + texel.y) % 2 == 0) ? vec3(0.9, 0.9, 0.9) : vec3(0.25, 0.3, 0.6);
#else
  result = vec3(0.5);
#endif
#elif TERM == TERM_PATCHES
#if HAS_PATCHES
  result = id_colour(texelFetch(u_triangle_patch, u_first_triangle + gl_PrimitiveID).r);
#else
  result = vec3(0.5);
#endif
#else
  result = reflectance;
#endif
  o_radiance = vec4(result, length(p - u_camera_position));
}
