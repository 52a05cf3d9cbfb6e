// Radiance (an RGBA32F texture) to display sRGB.
#include "tonemap.glsl"
in vec2 v_texcoord;
uniform sampler2D u_radiance;
uniform float u_exposure;
uniform int u_curve;
out vec4 o_colour;
void main() {
  // Nearest texel: exact at equal sizes, a plain upscale for the window's reduced-resolution
  // frames while the camera moves.
  vec3 radiance = texture(u_radiance, v_texcoord).rgb;
  o_colour = vec4(tonemap(radiance, u_exposure, u_curve), 1.0);
}
