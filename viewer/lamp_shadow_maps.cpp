#include "viewer/lamp_shadow_maps.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/gtc/matrix_transform.hpp>

#include "viewer/shadow_maps.h"

namespace lb {

namespace {

// An up vector for glm::lookAt that is not parallel to `direction`.
vec3 up_for(vec3 direction) {
  return std::abs(direction.y) < 0.9f ? vec3(0.0f, 1.0f, 0.0f) : vec3(1.0f, 0.0f, 0.0f);
}

float farthest_corner(const Bounds& bounds, vec3 from) {
  float result = 0.0f;
  for (int corner = 0; corner < 8; ++corner) {
    const vec3 q{(corner & 1) ? bounds.max.x : bounds.min.x,
                 (corner & 2) ? bounds.max.y : bounds.min.y,
                 (corner & 4) ? bounds.max.z : bounds.min.z};
    result = std::max(result, glm::length(q - from));
  }
  return result;
}

bool has_light(const Lamp& lamp) {
  return glm::max(lamp.intensity.x, glm::max(lamp.intensity.y, lamp.intensity.z)) > 0.0f;
}

}  // namespace

LampShadowMaps::LampShadowMaps(const GpuScene& scene, const DepthPrograms& programs,
                               const ShadowSettings& settings) {
  const std::vector<Lamp>& lamps = scene.scene().lights;
  lamps_.resize(lamps.size());
  resolution_ = std::clamp(settings.resolution, 16, 4096);
  const Bounds bounds = scene.bounds();
  const float diagonal = std::max(bounds.diagonal(), 1e-3f);
  const vec3 centre = bounds.empty() ? vec3(0.0f) : 0.5f * (bounds.min + bounds.max);
  // The scene's bounding sphere, 1% larger so its rim is not on the map's edge.
  const float radius = 0.505f * diagonal;
  const float near = 2e-3f * diagonal;  // as the area lights' cubes
  const float res = float(resolution_);

  int shadowed = 0;
  for (size_t l = 0; l < lamps.size(); ++l) {
    const Lamp& lamp = lamps[l];
    if (!has_light(lamp) || bounds.empty()) continue;
    if (shadowed == kMaxShadowedLamps) {
      ++unshadowed_;
      continue;
    }
    ++shadowed;
    LampShadow& s = lamps_[l];
    s.layer = layers_;
    const vec3 d = glm::normalize(lamp.direction);
    if (lamp.kind == LampKind::directional) {
      // Looking along the light from outside the sphere; depth spans [r, 3r] in [0.5r, 3.5r].
      const vec3 eye = centre - d * (2.0f * radius);
      s.matrix = glm::ortho(-radius, radius, -radius, radius, 0.5f * radius, 3.5f * radius) *
                 glm::lookAt(eye, centre, up_for(d));
      s.texel = {0.0f, 2.0f * radius / res};
      layers_ += 1;
      continue;
    }
    const float far = 1.05f * farthest_corner(bounds, lamp.position) + near;
    if (lamp.kind == LampKind::spot && lamp.outer_cone <= kMaxSpotMapHalfAngle) {
      // A square frustum whose inscribed cone is the outer cone, with a little margin.
      const float half = std::min(lamp.outer_cone + 0.02f, kMaxSpotMapHalfAngle + 0.02f);
      s.matrix = glm::perspective(2.0f * half, 1.0f, near, far) *
                 glm::lookAt(lamp.position, lamp.position + d, up_for(d));
      s.texel = {2.0f * std::tan(half) / res, 0.0f};
      layers_ += 1;
      continue;
    }
    s.cube = true;
    s.range = {near, far};
    s.texel = {2.0f / res, 0.0f};  // a 90-degree face spans 2 d
    layers_ += 6;
  }
  if (unshadowed_ > 0) {
    std::fprintf(stderr,
                 "lightbake: warning: %s: %d of %zu lamps cast no shadows in the viewer (it "
                 "draws shadow maps for the first %d)\n",
                 scene.scene().source_path.c_str(), unshadowed_, lamps.size(), kMaxShadowedLamps);
  }

  depth_ = make_depth_array(resolution_, layers_);
  if (layers_ == 0) return;
  gl::Framebuffer framebuffer = begin_shadow_pass(resolution_);
  programs.opaque->use();
  DrawCounts counts;
  auto draw_layer = [&](int layer, const glm::mat4& world_to_clip) {
    glFramebufferTextureLayer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, depth_.get(), 0, layer);
    glClear(GL_DEPTH_BUFFER_BIT);
    draw_shadow_casters(scene, programs, Frustum(world_to_clip), counts);
  };
  for (size_t l = 0; l < lamps.size(); ++l) {
    const LampShadow& s = lamps_[l];
    if (s.layer < 0) continue;
    if (!s.cube) {
      programs.set("u_use_matrix", 1);
      programs.set("u_shadow_matrix", s.matrix);
      draw_layer(s.layer, s.matrix);
      continue;
    }
    programs.set("u_use_matrix", 0);
    programs.set("u_shadow_near", s.range.x);
    programs.set("u_shadow_far", s.range.y);
    programs.set("u_cube_centre", lamps[l].position);
    for (int face = 0; face < 6; ++face) {
      programs.set("u_cube_face", face);
      draw_layer(s.layer + face, cube_face_matrix(lamps[l].position, face, s.range.x, s.range.y));
    }
  }
  programs.set("u_use_matrix", 0);
  end_shadow_pass();
  gl::check_errors("rendering lamp shadow maps");
}

}  // namespace lb
