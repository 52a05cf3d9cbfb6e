// Scene geometry: meshes are already in world space (the loaders apply transforms).
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec2 a_uv;
layout(location = 3) in vec2 a_lightmap_uv;
layout(location = 4) in vec4 a_tangent;
layout(location = 5) in vec3 a_radiance;  // vertex radiosity, E/pi (bake/bake_result.h)

uniform mat4 u_view_projection;
// Planar mirror pass: keep only what lies in front of the mirror (enabled with
// GL_CLIP_DISTANCE0 there, ignored otherwise).
uniform vec4 u_clip_plane;

out vec3 v_position;
out vec3 v_normal;
out vec2 v_uv;
out vec2 v_lightmap_uv;
out vec4 v_tangent;
out vec3 v_radiance;
// The depth pre-pass draws with this shader and another fragment shader, and the shading pass
// keeps the fragments at exactly that depth: the same gl_Position in both programs.
invariant gl_Position;

void main() {
  v_position = a_position;
  v_normal = a_normal;
  v_uv = a_uv;
  v_lightmap_uv = a_lightmap_uv;
  v_tangent = a_tangent;
  v_radiance = a_radiance;
  gl_Position = u_view_projection * vec4(a_position, 1.0);
  gl_ClipDistance[0] = dot(u_clip_plane, vec4(a_position, 1.0));
}
