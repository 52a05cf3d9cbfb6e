#include "viewer/shadow_maps.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>

#include "bake/sampling.h"
#include "viewer/occlusion_culler.h"

namespace lb {

namespace {

// Whether cube face `face` sees any direction in front of a one-sided emitter with normal n:
// the face spans directions e + s b + t c, |s|, |t| <= 1, so the best cosine is bounded by
// n.e + |n.b| + |n.c|.
bool face_sees_front(int face, vec3 n) {
  const int axis = face / 2;
  const float sign = (face % 2 == 0) ? 1.0f : -1.0f;
  const float major = sign * n[axis];
  return major + std::abs(n[(axis + 1) % 3]) + std::abs(n[(axis + 2) % 3]) > 1e-4f;
}

}  // namespace

int shadow_samples_per_light(const ShadowSettings& settings, size_t light_count,
                             int max_layers) {
  if (settings.samples_per_light > 0) return settings.samples_per_light;
  if (light_count == 0) return 0;
  const int lights = int(std::min<size_t>(light_count, std::numeric_limits<int>::max() / 6));
  const int wanted = std::clamp(settings.total_samples / lights, 2, 16);
  return std::max(1, std::min(wanted, max_layers / (6 * lights)));
}

int max_shadow_layers() {
  GLint layers = 0;
  glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &layers);
  return std::max(1, int(layers));
}

ShadowMaps::ShadowMaps(const GpuScene& scene, const DepthPrograms& programs,
                       const ShadowSettings& settings, LightLists* lists) {
  rebuild(scene, programs, settings, lists);
}

void ShadowMaps::rebuild(const GpuScene& scene, const DepthPrograms& programs,
                         const ShadowSettings& settings, LightLists* lists) {
  start_.clear();
  count_.clear();
  const auto& lights = scene.lights().lights;
  const int per_light = shadow_samples_per_light(settings, lights.size(), max_shadow_layers());
  resolution_ = std::clamp(settings.resolution, 16, 4096);
  const float diagonal = std::max(scene.bounds().diagonal(), 1e-3f);
  near_ = 2e-3f * diagonal;
  far_ = 1.05f * diagonal;

  // Points: a jittered sqrt(K) x sqrt(K) grid (rounded up) over each light, K kept.
  std::vector<vec3> points, normals;
  std::vector<int> light_of;  // per point
  for (size_t l = 0; l < lights.size(); ++l) {
    start_.push_back(int(points.size()));
    count_.push_back(per_light);
    const int side = int(std::ceil(std::sqrt(float(per_light))));
    const int rows = (per_light + side - 1) / side;
    // Cells in row order, but the four corner cells first: the shader stops after them when
    // they agree (shaders/shadows.glsl).
    std::vector<int> cells;
    if (per_light > 4 && per_light == side * rows) {
      cells = {0, side - 1, per_light - side, per_light - 1};
    }
    for (int k = 0; k < per_light; ++k) {
      if (std::find(cells.begin(), cells.end(), k) == cells.end()) cells.push_back(k);
    }
    // Interleaved sets: cell (i, j) of the K-cell grid is cell (n i + a, n j + b) of the
    // n-times finer grid, (a, b) this set's offset; each set has its own jitter.
    const int n = std::max(1, settings.interleave);
    const int set = std::clamp(settings.set, 0, n * n - 1);
    Rng rng(n == 1 ? hash_seed(settings.seed, l) : hash_seed(settings.seed, l, uint64_t(set) + 1));
    for (int k : cells) {
      const vec2 u = stratified(n * (k % side) + set % n, n * (k / side) + set / n, n * side,
                                n * rows, rng.next_2d());
      const LightSample sample = lights[l].sample(scene.scene(), u);
      // Just in front of the emitting face, so the light does not hide itself.
      points.push_back(sample.position + sample.normal * (1e-4f * diagonal));
      normals.push_back(sample.normal);
      light_of.push_back(int(l));
    }
  }
  points_count_ = points.size();
  points_ = gl::make_buffer_texture(GL_RGB32F, points.data(), points.size() * sizeof(vec3));

  const int layers = int(std::max<size_t>(1, 6 * points.size()));
  if (!depth_ || layers != layers_ || resolution_ != depth_resolution_) {
    depth_ = make_depth_array(resolution_, layers);
    layers_ = layers;
    depth_resolution_ = resolution_;
  }
  gl::Framebuffer framebuffer = begin_shadow_pass(resolution_);
  programs.set("u_shadow_near", near_);
  programs.set("u_shadow_far", far_);
  programs.set("u_use_matrix", 0);
  counts_ = DrawCounts();
  std::optional<OcclusionCuller> occlusion;
  if (scene.occlusion_culling()) occlusion.emplace(scene);
  for (size_t k = 0; k < points.size(); ++k) {
    programs.set("u_cube_centre", points[k]);
    for (int face = 0; face < 6; ++face) {
      glFramebufferTextureLayer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, depth_.get(), 0,
                                GLint(6 * k + size_t(face)));
      glClear(GL_DEPTH_BUFFER_BIT);
      const bool drawn = lights[size_t(light_of[k])].two_sided || face_sees_front(face, normals[k]);
      programs.set("u_cube_face", face);
      const Frustum frustum(cube_face_matrix(points[k], face, near_, far_));
      if (drawn && occlusion) {
        // A cube face's near plane reaches sqrt(3) near from its centre.
        occlusion->draw(scene, frustum, points[k], 2.0f * near_, GL_LESS, counts_);
        draw_alpha_cut(scene, programs, frustum, counts_, true);
      } else if (drawn) {
        draw_shadow_casters(scene, programs, frustum, counts_);
      }
      if (lists) lists->test_face(light_of[k], points[k], frustum, drawn, near_, resolution_);
    }
  }
  end_shadow_pass();
  if (lists) lists->finish(scene, points, start_, count_);
  gl::check_errors("rendering shadow cubes");
}

gl::Texture make_depth_array(int resolution, int layers) {
  layers = std::max(1, layers);
  // What the driver cannot hold fails here, naming the size, not later at an unrelated call:
  // the layer count has a limit GL can be asked for, memory only the allocation can tell.
  const double gib = 4.0 * double(resolution) * resolution * layers / (1024.0 * 1024 * 1024);
  auto refused = [&](const std::string& why) {
    char size[96];
    std::snprintf(size, sizeof(size), "%d faces of %d^2 texels (%.2f GiB of depth)", layers,
                  resolution, gib);
    return std::runtime_error(std::string("shadow maps: ") + size + " " + why +
                              "; lower --shadow-resolution or --shadow-samples");
  };
  const int max_layers = max_shadow_layers();
  if (layers > max_layers)
    throw refused("are more than the " + std::to_string(max_layers) +
                  " layers this OpenGL allows");
  gl::Texture depth = gl::make_texture();
  glBindTexture(GL_TEXTURE_2D_ARRAY, depth.get());
  glTexImage3D(GL_TEXTURE_2D_ARRAY, 0, GL_DEPTH_COMPONENT32F, resolution, resolution, layers, 0,
               GL_DEPTH_COMPONENT, GL_FLOAT, nullptr);
  const GLenum error = glGetError();
  if (error != GL_NO_ERROR) {
    glBindTexture(GL_TEXTURE_2D_ARRAY, 0);
    char code[48];
    std::snprintf(code, sizeof(code), "were refused (OpenGL error 0x%04x)", unsigned(error));
    throw refused(error == GL_OUT_OF_MEMORY ? "are more than this OpenGL can allocate" : code);
  }
  glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
  glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
  glBindTexture(GL_TEXTURE_2D_ARRAY, 0);
  return depth;
}

gl::Framebuffer begin_shadow_pass(int resolution) {
  gl::Framebuffer framebuffer = gl::make_framebuffer();
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer.get());
  glDrawBuffer(GL_NONE);
  glReadBuffer(GL_NONE);
  glViewport(0, 0, resolution, resolution);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  glDisable(GL_CULL_FACE);
  // Slope-scaled bias against acne on surfaces seen at grazing angles from the light: half the
  // depth a caster's slope spans across one texel, the most a texel's stored depth can lie
  // from the surface within it (shadows.glsl lifts the receiver up to half a texel for its
  // side). Twice the slope (and 4 units) cut the shadow where a thin wall stands on a floor at a
  // grazing light: Figure 3's ring wall, seen edge-on from the lamp at its sides, left the
  // cloth at its foot lit (direct term vs HQ's, MRE 0.58 -> 0.14; bench/results/LOG.md,
  // "shadow offsets"); a quarter shows acne (room_no_ball 0.0036 -> 0.0053).
  glEnable(GL_POLYGON_OFFSET_FILL);
  glPolygonOffset(0.5f, 1.0f);
  return framebuffer;
}

void draw_shadow_casters(const GpuScene& scene, const DepthPrograms& programs,
                         const Frustum& frustum, DrawCounts& counts) {
  for (size_t m = 0; m < scene.meshes().size(); ++m) {
    // Emitters cast no shadows: they are the lights (thin one-sided panels).
    if (scene.scene().materials[size_t(scene.meshes()[m].material)].is_emitter()) continue;
    if (programs.alpha_cut && alpha_cut(scene, m)) continue;
    scene.draw_mesh(m, frustum, counts);
  }
  glBindVertexArray(0);
  draw_alpha_cut(scene, programs, frustum, counts, true);
}

void end_shadow_pass() {
  glDisable(GL_POLYGON_OFFSET_FILL);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

}  // namespace lb
