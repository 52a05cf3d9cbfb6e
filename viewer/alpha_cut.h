#pragma once
// glTF alphaMode MASK and BLEND in the rasteriser (shaders/alpha.glsl): which meshes are cut,
// and what a draw of one needs. Their passes draw them with a program variant of their own
// (ALPHA_CUT) after the opaque meshes: a `discard` in the opaque meshes' shaders would cost
// every fragment its early depth test, and the occlusion culler never counts them as occluders.

#include "viewer/gpu_scene.h"
#include "viewer/shader_program.h"

namespace lb {

// Whether mesh `m`'s material cuts it (MASK) or makes it stochastically transparent (BLEND).
bool alpha_cut(const GpuScene& scene, size_t m);
// Whether any mesh is.
bool any_alpha_cut(const GpuScene& scene);

// The texture unit of the alpha texture in every pass (after viewer/renderer.cpp's units).
inline constexpr int kAlphaTextureUnit = 22;

// Sets `program`'s alpha.glsl uniforms for mesh `m`, its alpha texture bound to
// kAlphaTextureUnit.
void set_alpha_cut(const ShaderProgram& program, const GpuScene& scene, size_t m);

// The two variants of a depth-only pass: opaque, and ALPHA_CUT. A uniform is set in both.
struct DepthPrograms {
  const ShaderProgram* opaque = nullptr;
  const ShaderProgram* alpha_cut = nullptr;  // null when no mesh is cut

  template <class T>
  void set(const char* name, const T& value) const {
    if (alpha_cut) {
      alpha_cut->use();
      alpha_cut->set(name, value);
    }
    opaque->use();
    opaque->set(name, value);
  }
};

// Draws the cut meshes `frustum` may see with `programs.alpha_cut` (emitters too unless
// `casters_only`), marking them in `drawn` if given; leaves `programs.opaque` bound.
void draw_alpha_cut(const GpuScene& scene, const DepthPrograms& programs, const Frustum& frustum,
                    DrawCounts& counts, bool casters_only, std::vector<char>* drawn = nullptr,
                    const DetailView& detail = {});

}  // namespace lb
