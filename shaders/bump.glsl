// Bump mapping: Blinn's height-map perturbation and tangent-space normal maps.
// Without per-vertex tangents the surface frame comes from screen-space derivatives of the
// position and texture coordinates (Mikkelsen 2010, "Bump mapping unparametrized surfaces"),
// which is exact per triangle for the linear parametrisation of a mesh.
#ifndef LB_BUMP_GLSL
#define LB_BUMP_GLSL

const int BUMP_NONE = 0;
const int BUMP_HEIGHT = 1;
const int BUMP_NORMAL_MAP = 2;

uniform sampler2D u_bump_texture;
uniform float u_bump_scale;
// Mip level bias of the height samples (Renderer: RenderSettings::bump_full_resolution).
// Shading is not linear in the normal, so a normal taken from a height averaged over a pixel
// lights minified bumps too brightly (a 16-texel ridge at ~10 texels a pixel: +11% at bias -1,
// tests/viewer/test_viewer_lamps.cpp). Still images of several frames read the base level
// (bias -64): each frame aliases, their mean is the bumped shading (within 0.1% there). One
// frame reads one level finer than the pixel's (-1): measured best of 0..-3 on Figure 6's
// walls, direct term against HQ's: MRE 0.043 -> 0.033, energy +1.0% -> +0.2%.
uniform float u_bump_lod_bias;

// World-space gradients of u and v on the surface (the dual basis of dP/du, dP/dv).
void uv_gradients(vec3 p, vec2 uv, vec3 n, out vec3 grad_u, out vec3 grad_v) {
  vec3 dpdx = dFdx(p), dpdy = dFdy(p);
  vec2 duvdx = dFdx(uv), duvdy = dFdy(uv);
  vec3 r1 = cross(dpdy, n), r2 = cross(n, dpdx);
  float det = dot(dpdx, r1);
  if (abs(det) < 1e-20) { grad_u = vec3(0.0); grad_v = vec3(0.0); return; }
  grad_u = (r1 * duvdx.x + r2 * duvdy.x) / det;
  grad_v = (r1 * duvdx.y + r2 * duvdy.y) / det;
}

// Blinn (1978): displace the surface by h(u,v) = bump_scale * texture along n; to first order
// the normal becomes n - grad_s(h), with grad_s the surface gradient.
vec3 height_bump(vec3 p, vec2 uv, vec3 n) {
  vec2 size = vec2(textureSize(u_bump_texture, 0));
  vec2 du = vec2(1.0 / size.x, 0.0), dv = vec2(0.0, 1.0 / size.y);
  float b = u_bump_lod_bias;
  float hu = (texture(u_bump_texture, uv + du, b).r - texture(u_bump_texture, uv - du, b).r) /
             (2.0 * du.x);
  float hv = (texture(u_bump_texture, uv + dv, b).r - texture(u_bump_texture, uv - dv, b).r) /
             (2.0 * dv.y);
  vec3 grad_u, grad_v;
  uv_gradients(p, uv, n, grad_u, grad_v);
  vec3 surface_gradient = u_bump_scale * (hu * grad_u + hv * grad_v);
  return normalize(n - surface_gradient);
}

// glTF tangent-space normal map; bump_scale scales x and y.
vec3 normal_map_bump(vec3 p, vec2 uv, vec3 n, vec4 tangent) {
  // The same level bias as the height map's samples (above): mipmapped normals flatten bumps too.
  vec3 t_n = texture(u_bump_texture, uv, u_bump_lod_bias).xyz * 2.0 - 1.0;
  t_n.xy *= u_bump_scale;
  vec3 t, b;
  if (dot(tangent.xyz, tangent.xyz) > 1e-12) {
    t = normalize(tangent.xyz - n * dot(n, tangent.xyz));
    b = cross(n, t) * (tangent.w < 0.0 ? -1.0 : 1.0);
  } else {
    vec3 grad_u, grad_v;
    uv_gradients(p, uv, n, grad_u, grad_v);
    t = length(grad_u) > 0.0 ? normalize(grad_u) : vec3(1, 0, 0);
    // v grows downwards in glTF images, so +y of the normal map points along -grad_v.
    b = length(grad_v) > 0.0 ? -normalize(grad_v) : cross(n, t);
  }
  return normalize(t * t_n.x + b * t_n.y + n * t_n.z);
}

// BUMP_KIND is a define (scene.frag): only the chosen method is compiled in.
vec3 bumped_normal(vec3 p, vec2 uv, vec3 n, vec4 tangent) {
#if BUMP_KIND == 1
  return height_bump(p, uv, n);
#elif BUMP_KIND == 2
  return normal_map_bump(p, uv, n, tangent);
#else
  return n;
#endif
}

#endif
