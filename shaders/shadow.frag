// Depth only. With ALPHA_CUT, a masked or blended caster's cut-outs (alpha.glsl).
#ifdef ALPHA_CUT
#include "alpha.glsl"
in vec2 v_uv;
in vec3 v_world;
void main() {
  if (alpha_cut(v_uv, alpha_point_key(v_world))) discard;
}
#else
void main() {}
#endif
