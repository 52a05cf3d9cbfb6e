// Copies a frame's radiance; blended into the running mean of the still camera's frames
// (viewer/renderer.cpp: constant alpha 1 / (n + 1)).
uniform sampler2D u_frame_radiance;
out vec4 o_radiance;
void main() { o_radiance = texelFetch(u_frame_radiance, ivec2(gl_FragCoord.xy), 0); }
