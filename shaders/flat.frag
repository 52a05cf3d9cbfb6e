// The benchmark yardstick: the same geometry, one colour per material, no lighting.
uniform vec3 u_reflectance;
out vec4 o_radiance;
void main() { o_radiance = vec4(u_reflectance, 1.0); }
