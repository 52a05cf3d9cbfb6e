// The depth pre-pass (viewer/renderer.cpp draw_frame): depth only, no colour, so the shading
// pass that follows shades each pixel once. With ALPHA_CUT, scene.frag's cut-outs, the same
// fragments: the shading pass keeps only fragments at exactly this depth.
#ifdef ALPHA_CUT
#include "alpha.glsl"
in vec2 v_uv;
uniform uint u_frame;
void main() {
  if (alpha_cut(v_uv, alpha_pixel_key(u_frame))) discard;
}
#else
void main() {}
#endif
