// The sky behind the scene: drawn after the geometry at the far plane, so it shows only where
// no surface is. The view direction of a pixel comes from the inverse view-projection (the
// near and far points of its ray); the radiance mirrors lb::SkyLight::radiance
// (bake/sky_light.cpp): the constant times the equirect texel the direction falls in,
// unfiltered, with lb::direction_to_equirect's convention (+Y up, -Z at the image's centre).
// The sky's light on surfaces is baked (soft light), so nothing else here knows about it.
// Define: HAS_SKY_TEXTURE (0 or 1).
#include "common.glsl"

in vec2 v_texcoord;
uniform mat4 u_inverse_view_projection;
uniform vec3 u_sky_radiance;  // W/(sr m^2)
uniform sampler2D u_sky_texture;
out vec4 o_radiance;

void main() {
  vec2 ndc = 2.0 * v_texcoord - 1.0;
  vec4 near = u_inverse_view_projection * vec4(ndc, -1.0, 1.0);
  vec4 far = u_inverse_view_projection * vec4(ndc, 1.0, 1.0);
  vec3 d = normalize(far.xyz / far.w - near.xyz / near.w);
  vec3 radiance = u_sky_radiance;
#if HAS_SKY_TEXTURE
  float u = 0.5 + atan(d.x, -d.z) / TWO_PI;
  u -= floor(u);
  float v = acos(clamp(d.y, -1.0, 1.0)) / PI;
  ivec2 size = textureSize(u_sky_texture, 0);
  ivec2 texel = clamp(ivec2(vec2(u, v) * vec2(size)), ivec2(0), size - 1);
  radiance *= texelFetch(u_sky_texture, texel, 0).rgb;
#endif
  // alpha: distance, as scene.frag; the sky is farther than an environment search reaches
  // (viewer/environment_cubes.cpp kNothingDistance).
  o_radiance = vec4(radiance, 1e4);
  gl_FragDepth = 1.0;
}
