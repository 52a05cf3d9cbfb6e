// Shadow pass: world positions into one face of a light sample's depth cube.
#include "shadows.glsl"
layout(location = 0) in vec3 a_position;
uniform vec3 u_cube_centre;
uniform int u_cube_face;
void main() { gl_Position = cube_face_clip(a_position - u_cube_centre, u_cube_face); }
