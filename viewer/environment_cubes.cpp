#include "viewer/environment_cubes.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <numeric>

namespace lb {

namespace {

// Face sizes (texels). A sharp mirror shows its cube's texels at full size. Standing on a
// floor, it reflects the floor at its foot, which the cube (captured without the object) sees
// from the centre at a grazing angle, where a texel spans millimetres of floor, including the
// strip under the object's wall that the wall hides (Figure 3's cloth is lit there: the shadow
// lookup's margin reaches past the ring's 0.5 mm gap). The lookup's filtering carried that
// strip into the reflection as bright lines along the ring's foot
// (tests/viewer/test_viewer_mirror_ring.cpp). Against `lightbake reference` (320x240, 1024
// spp, default bakes) 256 for every cube: fig3_ring 0.0218 -> 0.0181 MRE (snapshot +0.24 CPU
// s), fig7_glass 0.0238 -> 0.0236 (+0.5 s), cornell_glass 0.0522 -> 0.0524, fig6_bump's glossy
// legs 0.0152 either way (+0.44 s; they read blurred mip levels); so mirrors get 256 and the
// rest 128. 512 gave fig3 0.0174 for another +0.7 s.
constexpr int kEnvironmentTexels = 128;
constexpr int kMirrorEnvironmentTexels = 256;
// What a capture's empty directions hold as distance (m): beyond any ray march's reach, so
// they read as infinitely far (shaders/sky.frag writes the same).
constexpr float kNothingDistance = 1e4f;

bool touch(const Bounds& a, const Bounds& b) {
  return glm::all(glm::lessThanEqual(a.min, b.max)) && glm::all(glm::lessThanEqual(b.min, a.max));
}

int find_root(std::vector<int>& parent, int i) {
  while (parent[size_t(i)] != i) i = parent[size_t(i)] = parent[size_t(parent[size_t(i)])];
  return i;
}

// Six faces around `centre` into a new cube map, with mip levels so glossy metal can read a
// blurred one. The shared cube keeps the viewer's old RGBA16F; object cubes hold the distance
// in alpha at full float precision for the ray march.
gl::Texture capture(vec3 centre, const std::vector<int>& skip, float diagonal, int texels,
                    bool full_float, const EnvironmentCubes::DrawCapture& draw,
                    bool normals = false) {
  gl::Texture cube = gl::make_texture();
  glBindTexture(GL_TEXTURE_CUBE_MAP, cube.get());
  for (int face = 0; face < 6; ++face) {
    glTexImage2D(GLenum(GL_TEXTURE_CUBE_MAP_POSITIVE_X + face), 0,
                 full_float ? GL_RGBA32F : GL_RGBA16F, texels, texels, 0,
                 GL_RGBA, GL_FLOAT, nullptr);
  }
  glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
  gl::Texture depth = gl::make_texture();
  glBindTexture(GL_TEXTURE_2D, depth.get());
  glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT32F, texels, texels, 0, GL_DEPTH_COMPONENT,
               GL_FLOAT, nullptr);
  gl::Framebuffer framebuffer = gl::make_framebuffer();
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer.get());
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, depth.get(), 0);
  glViewport(0, 0, texels, texels);
  glEnable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  // The GL cube map face conventions (OpenGL 4.6 spec, table 8.19).
  const vec3 directions[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  const vec3 ups[6] = {{0, -1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, {0, -1, 0}, {0, -1, 0}};
  const glm::mat4 projection =
      glm::perspective(glm::radians(90.0f), 1.0f, 1e-4f * diagonal, 2.0f * diagonal);
  for (int face = 0; face < 6; ++face) {
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0,
                           GLenum(GL_TEXTURE_CUBE_MAP_POSITIVE_X + face), cube.get(), 0);
    glClearColor(0, 0, 0, normals ? 0.0f : full_float ? kNothingDistance : 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    // With these up vectors, window x and y run along the face's s and t axes.
    const glm::mat4 view = glm::lookAt(centre, centre + directions[face], ups[face]);
    draw(projection * view, centre, skip, normals);
  }
  glClearColor(0, 0, 0, 1);
  glBindTexture(GL_TEXTURE_CUBE_MAP, cube.get());
  glGenerateMipmap(GL_TEXTURE_CUBE_MAP);
  glBindTexture(GL_TEXTURE_CUBE_MAP, 0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  gl::check_errors("capturing the environment");
  return cube;
}

}  // namespace

EnvironmentCubes::EnvironmentCubes(const GpuScene& scene, const DrawCapture& draw) {
  const std::vector<GpuMesh>& meshes = scene.meshes();
  const int count = int(meshes.size());
  cube_of_mesh_.assign(size_t(count), -1);
  auto specular = [&](int m) {
    return !scene.scene().materials[size_t(meshes[size_t(m)].material)].is_diffuse() &&
           !meshes[size_t(m)].bounds.empty();
  };
  auto curved = [&](int m) { return specular(m) && !meshes[size_t(m)].planar; };

  // Objects: curved specular meshes joined when their bounds touch (union-find).
  std::vector<int> parent(static_cast<size_t>(count));
  std::iota(parent.begin(), parent.end(), 0);
  for (int a = 0; a < count; ++a) {
    for (int b = a + 1; b < count && curved(a); ++b) {
      if (curved(b) && touch(meshes[size_t(a)].bounds, meshes[size_t(b)].bounds))
        parent[size_t(find_root(parent, b))] = find_root(parent, a);
    }
  }
  struct Object {
    std::vector<int> meshes;
    Bounds bounds;
  };
  std::vector<Object> objects;
  std::vector<int> object_of_root(size_t(count), -1);
  for (int m = 0; m < count; ++m) {
    if (!curved(m)) continue;
    int& index = object_of_root[size_t(find_root(parent, m))];
    if (index < 0) {
      index = int(objects.size());
      objects.emplace_back();
    }
    objects[size_t(index)].meshes.push_back(m);
    objects[size_t(index)].bounds.extend(meshes[size_t(m)].bounds.min);
    objects[size_t(index)].bounds.extend(meshes[size_t(m)].bounds.max);
  }
  // The largest first; ties keep mesh order, so the choice does not depend on anything else.
  std::stable_sort(objects.begin(), objects.end(), [](const Object& a, const Object& b) {
    return a.bounds.diagonal() > b.bounds.diagonal();
  });

  const float diagonal = std::max(scene.bounds().diagonal(), 1e-3f);
  for (size_t o = 0; o < objects.size() && o < size_t(kMaxObjectCubes); ++o) {
    EnvironmentCube cube;
    cube.centre = 0.5f * (objects[o].bounds.min + objects[o].bounds.max);
    cube.parallax = true;
    cube.meshes = objects[o].meshes;
    bool glass = false, mirror = true;
    for (int m : cube.meshes) {
      const MaterialKind kind = scene.scene().materials[size_t(meshes[size_t(m)].material)].kind;
      glass |= kind == MaterialKind::glass;
      mirror &= kind == MaterialKind::mirror;
    }
    cube.texels = mirror ? kMirrorEnvironmentTexels : kEnvironmentTexels;
    cube.texture = capture(cube.centre, cube.meshes, diagonal, cube.texels, true, draw);
    if (glass) {
      std::vector<int> others;
      for (int m = 0; m < count; ++m)
        if (std::find(cube.meshes.begin(), cube.meshes.end(), m) == cube.meshes.end())
          others.push_back(m);
      cube.self = capture(cube.centre, others, diagonal, cube.texels, true, draw, true);
      cube.size = objects[o].bounds.diagonal();
    }
    for (int m : cube.meshes) cube_of_mesh_[size_t(m)] = int(cubes_.size());
    cubes_.push_back(std::move(cube));
  }
  object_cubes_ = int(cubes_.size());

  // The shared cube, only when some specular mesh has no cube of its own (planar ones keep it
  // for the frames their planar pass is capped away): centred on all specular meshes, without
  // the one when there is only one.
  Bounds all;
  int specular_count = 0, specular_mesh = -1;
  bool shared_needed = false;
  for (int m = 0; m < count; ++m) {
    if (!specular(m)) continue;
    all.extend(meshes[size_t(m)].bounds.min);
    all.extend(meshes[size_t(m)].bounds.max);
    ++specular_count;
    specular_mesh = m;
    shared_needed |= cube_of_mesh_[size_t(m)] < 0;
  }
  if (shared_needed) {
    EnvironmentCube cube;
    cube.centre = 0.5f * (all.min + all.max);
    cube.texels = kEnvironmentTexels;
    cube.texture = capture(
        cube.centre, specular_count == 1 ? std::vector<int>{specular_mesh} : std::vector<int>{},
        diagonal, cube.texels, false, draw);
    for (int m = 0; m < count; ++m) {
      if (specular(m) && cube_of_mesh_[size_t(m)] < 0) {
        cube_of_mesh_[size_t(m)] = int(cubes_.size());
        cube.meshes.push_back(m);
      }
    }
    cubes_.push_back(std::move(cube));
  }
}

const EnvironmentCube* EnvironmentCubes::cube_for(int mesh) const {
  if (mesh < 0 || size_t(mesh) >= cube_of_mesh_.size() || cube_of_mesh_[size_t(mesh)] < 0)
    return nullptr;
  return &cubes_[size_t(cube_of_mesh_[size_t(mesh)])];
}

}  // namespace lb
