// Shadow pass: world positions into one face of a light sample's depth cube, or through a
// lamp's shadow matrix (spot perspective, directional orthographic).
#include "shadows.glsl"
layout(location = 0) in vec3 a_position;
layout(location = 2) in vec2 a_uv;
uniform vec3 u_cube_centre;
uniform int u_cube_face;
uniform int u_use_matrix;  // 1: u_shadow_matrix, 0: the cube face
uniform mat4 u_shadow_matrix;
out vec2 v_uv;     // for alpha cut-outs (shadow.frag)
out vec3 v_world;
void main() {
  v_uv = a_uv;
  v_world = a_position;
  gl_Position = u_use_matrix != 0 ? u_shadow_matrix * vec4(a_position, 1.0)
                                  : cube_face_clip(a_position - u_cube_centre, u_cube_face);
}
