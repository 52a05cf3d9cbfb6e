// glTF alphaMode in the rasteriser, as the ray tracer reads it (bake/accel.cpp): MASK drops the
// fragments whose alpha is below the cutoff; BLEND keeps a fragment with probability alpha
// (stochastic transparency: the accumulated frames and the shadow maps' filtering average it).
// Alpha is read at the base level, bilinearly, as the ray tracer reads it: a mip would thin
// and shift the cut with distance.
#include "hash.glsl"
uniform sampler2D u_alpha_texture;  // one channel (swizzled to .r)
uniform bool u_alpha_textured;
uniform float u_alpha_factor;
uniform float u_alpha_cutoff;  // MASK's; negative for BLEND

// `key`: what the BLEND coin depends on (a pixel and frame, or a point in space).
bool alpha_cut(vec2 uv, uvec3 key) {
  float alpha = u_alpha_factor * (u_alpha_textured ? textureLod(u_alpha_texture, uv, 0.0).r : 1.0);
  if (u_alpha_cutoff >= 0.0) return alpha < u_alpha_cutoff;
  uint h = hash_uint(key.x ^ hash_uint(key.y ^ hash_uint(key.z + 0x9e3779b9u)));
  return alpha <= float(h >> 8) * (1.0 / 16777216.0);
}

// A camera pass's coin: per pixel and frame, so the frames accumulated average it.
uvec3 alpha_pixel_key(uint frame) { return uvec3(uvec2(gl_FragCoord.xy), frame); }
// A shadow map's coin: per point of the surface (millimetre cells), the same every rebuild.
uvec3 alpha_point_key(vec3 p) { return uvec3(ivec3(floor(p * 1000.0))); }
