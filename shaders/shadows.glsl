// Soft shadows from several shadow "cubes" per light, rendered once per scene and cached.
//
// Each light gets K points spread over its area (stratified, jittered, fixed seed). From
// each point a depth cube is rendered (faces that see nothing in front of the one-sided
// emitter are skipped). A fragment's visibility of the light is the average over the K
// points of a 2x2 PCF depth test, so the penumbra follows the size of the light: sharp for a
// small light, wide for a large one, computed per fragment, and it costs K texture lookups.
// The cube faces live as layers of one depth texture array (GL 3.3 has no cube arrays); the
// face projection below is shared by the shadow pass (vertex shader) and the lookup, so they
// always agree. Weighting each point by its cos cos / r^2 share of the irradiance was tried
// and measured slightly worse on the Cornell box (0.0355 vs 0.0347; again with 2 x 2
// sub-pixel frames, 0.0209 vs 0.0205), so the mean is plain. Its error is mostly where one
// set of K jittered points happens to fall (a plate's penumbra: -4.9% .. +7.5% in sum over
// seeds 1..5 at K = 16), which still images reduce with interleaved sets, one a sub-pixel
// frame (ShadowSettings::interleave, viewer/snapshot.cpp).
#ifndef LB_SHADOWS_GLSL
#define LB_SHADOWS_GLSL

uniform float u_shadow_near;
uniform float u_shadow_far;

// Clip-space position of world offset d (from the cube centre) in cube face `face`
// (0..5 = +x, -x, +y, -y, +z, -z): a 90-degree perspective along the face axis, depth from
// near to far.
vec4 cube_face_clip_range(vec3 d, int face, float near, float far) {
  int axis = face / 2;
  float sign = (face % 2 == 0) ? 1.0 : -1.0;
  vec3 r = (axis == 0) ? d.xyz : (axis == 1) ? d.yzx : d.zxy;  // major, then the other two
  float m = sign * r.x;
  float a = (far + near) / (far - near);
  float b = -2.0 * far * near / (far - near);
  return vec4(r.y, r.z, a * m + b, m);
}

// The area lights' cubes, which share one near and far plane.
vec4 cube_face_clip(vec3 d, int face) {
  return cube_face_clip_range(d, face, u_shadow_near, u_shadow_far);
}

int cube_face_of(vec3 d) {
  vec3 a = abs(d);
  if (a.x >= a.y && a.x >= a.z) return d.x >= 0.0 ? 0 : 1;
  if (a.y >= a.z) return d.y >= 0.0 ? 2 : 3;
  return d.z >= 0.0 ? 4 : 5;
}

#ifdef SHADOW_LOOKUP
#include "lights.glsl"
const float kShadowRayOffsetTan = 4.0;
uniform sampler2DArrayShadow u_shadow_maps;
uniform samplerBuffer u_shadow_points;  // light sample points, RGB32F, one per cube
uniform int u_shadow_resolution;
// u_light_data is lights.glsl's: texel LIGHT_TEXELS * i + 1 .zw holds light i's first cube
// and its cube count.

// Whether the light's sample point `centre` (cube `cube`) sees p, filtered: in [0, 1].
float cube_visibility(int cube, vec3 centre, vec3 p, vec3 ng) {
  vec3 d = p - centre;
  float dist = length(d);
  // Self-shadowing margin: p moves toward the light point by half a texel times tan(theta),
  // theta between the normal and the point (a 90-degree face spans 2*dist), which is the depth
  // half a texel of a surface at theta spans; the shadow pass's slope-scaled polygon offset adds
  // to it. Moving along the light ray keeps p on its own shadow-map ray, so shadow edges stay
  // where they are. Holbert's normal offset, used before, gives the same margin but moves p
  // across the ray as well, and with it every edge by half a texel sin(theta) tan(theta) along
  // the receiver: fig3's ring cast a shadow a pixel short, and its mirror walls, reflecting the
  // foot, showed that strip as bright bands (raster against `lightbake reference`, 320x240:
  // direct term MRE 0.0342 -> 0.0150, whole image 0.0253 -> 0.0218, fig4 0.0256 -> 0.0246, the
  // other seven scenes within 0.0001). 0.3 texel shows acne (fig3 0.0267), 0.7 is no better
  // (0.0225). Past tan(theta) = kShadowRayOffsetTan the rest of the margin comes from the normal
  // offset (at most half a texel), so grazing receivers, which get little light, do not reach
  // far toward the light (viewer/light_lists.cpp grows its boxes by as much); all along the
  // ray, faces that see the light straddle their horizon showed acne (RasterVsHq: raster / HQ
  // 0.961 with the ray's part capped at tan 9.95). The price of the ray's part: an occluder
  // within the margin of a receiver along the ray does not shadow it, e.g. under a thin shell's
  // rim at its contact.
  float texel = 2.0 * dist / float(u_shadow_resolution);
  float cos_light = clamp(dot(ng, -d) / max(dist, 1e-30), 0.0, 1.0);
  float sin_light = sqrt(1.0 - cos_light * cos_light);
  float tan_light = sin_light / max(cos_light, 1e-6);
  vec3 q = d * (1.0 - 0.5 * texel * min(tan_light, kShadowRayOffsetTan) / max(dist, 1e-30)) +
           ng * (0.5 * texel * max(sin_light - kShadowRayOffsetTan * cos_light, 0.0));
  int face = cube_face_of(q);
  vec4 clip = cube_face_clip(q, face);
  vec3 ndc = clip.xyz / clip.w;
  float depth = 0.5 * ndc.z + 0.5;
  float layer = float(6 * cube + face);
  return texture(u_shadow_maps, vec4(0.5 * ndc.xy + 0.5, layer, depth));
}

// Fraction of light `index` that p (geometric normal ng) sees, in [0, 1].
float light_visibility(int index, vec3 p, vec3 ng) {
  vec2 cubes = texelFetch(u_light_data, LIGHT_TEXELS * index + 1).zw;
  int start = int(cubes.x);
  int count = int(cubes.y);
  if (count == 0) return 1.0;
  float visible = 0.0;
  float above = 0.0;  // points above p's horizon: the others add nothing to the irradiance
  for (int k = 0; k < count; ++k) {
    vec3 centre = texelFetch(u_shadow_points, start + k).xyz;
    if (dot(ng, p - centre) >= 0.0) continue;
    above += 1.0;
    visible += cube_visibility(start + k, centre, p, ng);
    // The first four points are the light's extreme corners (shadow_maps.cpp): when all four
    // see p it almost surely sees the whole light, so stop there (kept on purpose: without it
    // the Cornell box's direct-term error moved only from 0.0348 to 0.0345 MRE, and fully lit
    // fragments would pay K lookups, not 4). Not so for umbra, whose shortcut is gone: the points
    // are jittered inside their corner cells, and a fragment that four of them cannot see may
    // still see the light's rim. That shortcut made the Cornell box's penumbrae too dark: its
    // direct term's mean relative error against the reference was 0.0378 at the default K and
    // 0.0343 at K = 64, without it 0.0347 and 0.0295.
    if (k == 3 && count > 4 && visible == 4.0) return 1.0;
  }
  return above > 0.0 ? visible / above : 1.0;
}

// An unbiased one-lookup estimate of light_visibility without its corner shortcut, for the
// stochastic path (light_pick.glsl): point k = floor(u * count), u uniform in [0, 1), counts
// count / above times if it is above p's horizon, 0 if not (so the mean over u is
// visible / above).
float light_visibility_one(int index, vec3 p, vec3 ng, float u) {
  vec2 cubes = texelFetch(u_light_data, LIGHT_TEXELS * index + 1).zw;
  int start = int(cubes.x);
  int count = int(cubes.y);
  if (count == 0) return 1.0;
  float above = 0.0;
  for (int k = 0; k < count; ++k) {
    if (dot(ng, p - texelFetch(u_shadow_points, start + k).xyz) < 0.0) above += 1.0;
  }
  if (above == 0.0) return 1.0;
  int k = start + min(int(u * float(count)), count - 1);
  vec3 centre = texelFetch(u_shadow_points, k).xyz;
  if (dot(ng, p - centre) >= 0.0) return 0.0;
  return cube_visibility(k, centre, p, ng) * (float(count) / above);
}
#endif

#endif
