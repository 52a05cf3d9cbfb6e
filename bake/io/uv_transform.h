#pragma once
// KHR_texture_transform: the affine map a glTF textureInfo applies to its texture coordinates
// before sampling. The glTF loader applies it to a mesh's `uvs` when it reads them (docs/gltf.md).

#include <glm/glm.hpp>

namespace lb {

struct UvTransform {
  int tex_coord = 0;       // which TEXCOORD_n the texture is sampled with
  glm::dmat3 matrix{1.0};  // homogeneous: uv' = matrix * (u, v, 1)
  bool operator==(const UvTransform& other) const {
    return tex_coord == other.tex_coord && matrix == other.matrix;
  }
};

// T(offset) * R(rotation) * S(scale), per the extension: scale first, then rotate by `rotation`
// radians "counter-clockwise" (u' = cos u + sin v, v' = -sin u + cos v, the reading under which
// the spec's example, offset (0, 1), rotation pi/2, scale 0.5, samples the lower left quadrant
// of the image), then offset.
glm::dmat3 uv_transform_matrix(glm::dvec2 offset, double rotation, glm::dvec2 scale);

glm::vec2 apply_uv_transform(const glm::dmat3& matrix, glm::vec2 uv);

}  // namespace lb
