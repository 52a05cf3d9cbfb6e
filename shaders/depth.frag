// The depth pre-pass (viewer/renderer.cpp draw_frame): depth only, no colour, so the shading
// pass that follows shades each pixel once.
void main() {}
