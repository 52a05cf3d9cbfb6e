// Shared constants and small helpers. Every shader gets `#version 330 core` and its defines
// prepended by the loader (viewer/shader_program.cpp); `#include "x.glsl"` pulls in a chunk.
#ifndef LB_COMMON_GLSL
#define LB_COMMON_GLSL

const float PI = 3.14159265358979;
const float TWO_PI = 6.28318530717959;

// Debug outputs (lb::Term in viewer/render_settings.h; keep the numbers equal). Macros, since
// scene.frag picks the output with #if on the TERM define.
#define TERM_ALL 0
#define TERM_DIRECT 1
#define TERM_CAUSTIC 2
#define TERM_RADIOSITY 3
#define TERM_AMBIENT 4
#define TERM_SPECULAR 5
#define TERM_NORMALS 6
#define TERM_TEXEL_DENSITY 7
#define TERM_PATCHES 8
#define TERM_REFLECTANCE 9
#define TERM_BAKED 10

// Material kinds (lb::MaterialKind).
const int KIND_DIFFUSE = 0;
const int KIND_MIRROR = 1;
const int KIND_GLASS = 2;
const int KIND_GLOSSY = 3;

// A well-spread colour for an integer id (patches), in [0.2, 1].
vec3 id_colour(uint id) {
  uint h = id * 747796405u + 2891336453u;
  h = ((h >> ((h >> 28u) + 4u)) ^ h) * 277803737u;
  h = (h >> 22u) ^ h;
  return vec3(0.2) + 0.8 * vec3(float(h & 255u), float((h >> 8u) & 255u),
                                float((h >> 16u) & 255u)) / 255.0;
}

#endif
