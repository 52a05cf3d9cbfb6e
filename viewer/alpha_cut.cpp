#include "viewer/alpha_cut.h"

namespace lb {

bool alpha_cut(const GpuScene& scene, size_t m) {
  const Material& material = scene.scene().materials[size_t(scene.meshes()[m].material)];
  return material.alpha_mask || material.alpha_blend;
}

bool any_alpha_cut(const GpuScene& scene) {
  for (size_t m = 0; m < scene.meshes().size(); ++m)
    if (alpha_cut(scene, m)) return true;
  return false;
}

void set_alpha_cut(const ShaderProgram& program, const GpuScene& scene, size_t m) {
  const Material& material = scene.scene().materials[size_t(scene.meshes()[m].material)];
  const GLuint texture = scene.texture(material.alpha_texture);
  glActiveTexture(GLenum(GL_TEXTURE0 + kAlphaTextureUnit));
  glBindTexture(GL_TEXTURE_2D, texture);
  glActiveTexture(GL_TEXTURE0);
  program.set("u_alpha_texture", kAlphaTextureUnit);
  program.set("u_alpha_textured", int(texture != 0));
  program.set("u_alpha_factor", material.alpha_factor);
  program.set("u_alpha_cutoff", material.alpha_mask ? material.alpha_cutoff : -1.0f);
}

void draw_alpha_cut(const GpuScene& scene, const DepthPrograms& programs, const Frustum& frustum,
                    DrawCounts& counts, bool casters_only, std::vector<char>* drawn,
                    const DetailView& detail) {
  if (!programs.alpha_cut) return;
  bool bound = false;
  for (size_t m = 0; m < scene.meshes().size(); ++m) {
    if (!alpha_cut(scene, m)) continue;
    if (casters_only && scene.scene().materials[size_t(scene.meshes()[m].material)].is_emitter())
      continue;
    if (drawn) (*drawn)[m] = 1;
    if (scene.culled(m, frustum, counts)) continue;
    if (!bound) programs.alpha_cut->use(), bound = true;
    set_alpha_cut(*programs.alpha_cut, scene, m);
    scene.draw_mesh(m, frustum, counts, detail);
  }
  glBindVertexArray(0);
  programs.opaque->use();
}

}  // namespace lb
