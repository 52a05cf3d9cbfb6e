#include "bake/surface.h"

#include <algorithm>
#include <cmath>

namespace lb {

template <class T>
static T interpolate(const std::vector<T>& values, uvec3 tri, vec2 b) {
  return (1.0f - b.x - b.y) * values[tri.x] + b.x * values[tri.y] + b.y * values[tri.z];
}

SurfacePoint surface_at(const Scene& scene, const Hit& hit, const Ray& ray) {
  const Mesh& mesh = scene.meshes[hit.mesh];
  const uvec3 tri = mesh.triangles[hit.triangle];
  SurfacePoint sp;
  sp.mesh = hit.mesh;
  sp.triangle = hit.triangle;
  sp.barycentric = hit.barycentric;
  // Interpolating the vertices is more precise than origin + t * direction far from the origin.
  sp.position = interpolate(mesh.positions, tri, hit.barycentric);
  sp.geometric_normal = hit.geometric_normal;
  sp.shading_normal = sp.geometric_normal;
  if (!mesh.normals.empty()) {
    const vec3 n = interpolate(mesh.normals, tri, hit.barycentric);
    const float length = glm::length(n);
    if (length > 0.0f) sp.shading_normal = n / length;
  }
  if (!mesh.uvs.empty()) sp.uv = interpolate(mesh.uvs, tri, hit.barycentric);
  if (!mesh.lightmap_uvs.empty()) sp.lightmap_uv = interpolate(mesh.lightmap_uvs, tri, hit.barycentric);
  if (!mesh.tangents.empty()) sp.tangent = interpolate(mesh.tangents, tri, hit.barycentric);
  sp.material = &scene.materials[size_t(mesh.material)];
  (void)ray;
  return sp;
}

namespace {

// Texel index i of a row or column of n texels, as the wrap mode addresses it.
int wrap_texel(int i, int n, TextureWrap wrap) {
  switch (wrap) {
    case TextureWrap::clamp:
      return std::clamp(i, 0, n - 1);
    case TextureWrap::mirror: {
      const int period = 2 * n, r = ((i % period) + period) % period;
      return r < n ? r : period - 1 - r;
    }
    case TextureWrap::repeat:
      break;
  }
  const int r = i % n;
  return r < 0 ? r + n : r;
}

}  // namespace

vec4 sample_texture(const Texture& texture, vec2 uv) {
  if (texture.width <= 0 || texture.height <= 0 || texture.texels.empty()) return vec4(1.0f);
  const int channels = std::min(texture.channels, 4);
  auto texel = [&](int i, int j) {
    const size_t index =
        (size_t(j) * size_t(texture.width) + size_t(i)) * size_t(texture.channels);
    vec4 v(1.0f);
    for (int c = 0; c < channels; ++c) v[c] = texture.texels[index + size_t(c)];
    if (texture.channels == 1) v = vec4(v.x, v.x, v.x, 1.0f);
    return v;
  };
  if (texture.filter == TextureFilter::nearest)
    return texel(wrap_texel(int(std::floor(uv.x * float(texture.width))), texture.width,
                            texture.wrap_u),
                 wrap_texel(int(std::floor(uv.y * float(texture.height))), texture.height,
                            texture.wrap_v));
  const float x = uv.x * float(texture.width) - 0.5f;
  const float y = uv.y * float(texture.height) - 0.5f;
  const float fx = std::floor(x), fy = std::floor(y);
  const float tx = x - fx, ty = y - fy;
  const int i0 = wrap_texel(int(fx), texture.width, texture.wrap_u);
  const int j0 = wrap_texel(int(fy), texture.height, texture.wrap_v);
  const int i1 = wrap_texel(int(fx) + 1, texture.width, texture.wrap_u);
  const int j1 = wrap_texel(int(fy) + 1, texture.height, texture.wrap_v);
  return (1 - tx) * (1 - ty) * texel(i0, j0) + tx * (1 - ty) * texel(i1, j0) +
         (1 - tx) * ty * texel(i0, j1) + tx * ty * texel(i1, j1);
}

vec3 reflectance_at(const Scene& scene, const SurfacePoint& sp) {
  const Material& material = *sp.material;
  if (material.reflectance_texture < 0) return material.reflectance;
  return material.reflectance *
         vec3(sample_texture(scene.textures[size_t(material.reflectance_texture)], sp.uv));
}

}  // namespace lb
