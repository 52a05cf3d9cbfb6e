#include "viewer/renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <optional>
#include <stdexcept>

#include "bake/bsdf.h"

namespace lb {

namespace {

// Texture units, one per sampler so samplers of different types never share a unit.
enum Unit : int {
  kUnitLightTriangles = 0,
  kUnitShadowPoints,
  kUnitShadowMaps,
  kUnitReflectance,
  kUnitBump,
  kUnitLightmap,
  kUnitPatches,
  kUnitEnvironment,
  kUnitRadiance,
  kUnitPlanar,
  kUnitLightOutlines,
  kUnitSoftLight,
  kUnitLampShadowMaps,
  kUnitSky,
  kUnitLightData,
  kUnitLampData,
  kUnitFrame,
  kUnitEnvironmentSelf,
  kUnitLightList,
  kUnitLightmapL1X,
  kUnitLightmapL1Y,
  kUnitLightmapL1Z,
  kUnitAlpha,
  kUnitSoftLightL1X,
  kUnitSoftLightL1Y,
  kUnitSoftLightL1Z,
};
static_assert(kUnitAlpha == kAlphaTextureUnit);

void bind(int unit, GLenum target, GLuint texture) {
  glActiveTexture(GLenum(GL_TEXTURE0 + unit));
  glBindTexture(target, texture);
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// An RGBA32F colour target with a depth buffer (depth may be skipped).
void make_target(int width, int height, bool with_depth, gl::Framebuffer& framebuffer,
                 gl::Texture& colour, gl::Texture& depth) {
  colour = gl::make_texture();
  glBindTexture(GL_TEXTURE_2D, colour.get());
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, width, height, 0, GL_RGBA, GL_FLOAT, nullptr);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  framebuffer = gl::make_framebuffer();
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer.get());
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, colour.get(), 0);
  if (with_depth) {
    depth = gl::make_texture();
    glBindTexture(GL_TEXTURE_2D, depth.get());
    // With stencil, for the depth pre-pass (Renderer::draw_frame).
    glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH32F_STENCIL8, width, height, 0, GL_DEPTH_STENCIL,
                 GL_FLOAT_32_UNSIGNED_INT_24_8_REV, nullptr);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_TEXTURE_2D, depth.get(),
                           0);
  }
  glBindTexture(GL_TEXTURE_2D, 0);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    throw std::runtime_error("the radiance framebuffer is incomplete");
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

// Twice the distance from `eye` to the farthest corner of `view_projection`'s near plane: boxes
// that close may be clipped by it, so the occlusion culler draws them untested.
float near_reach(const glm::mat4& view_projection, vec3 eye) {
  const glm::dmat4 inverse = glm::inverse(glm::dmat4(view_projection));
  double reach = 0.0;
  for (int c = 0; c < 4; ++c) {
    const glm::dvec4 corner((c & 1) ? 1.0 : -1.0, (c & 2) ? 1.0 : -1.0, -1.0, 1.0);
    const glm::dvec4 p = inverse * corner;
    reach = std::max(reach, glm::length(glm::dvec3(p) / p.w - glm::dvec3(eye)));
  }
  return float(2.0 * reach);
}

// The projection whose pixels sample at their centre plus `offset` pixels (x right, y up): the
// image moves the other way, by 2 offset / size in NDC (a clip-space shift times w).
glm::mat4 offset_projection(const glm::mat4& projection, vec2 offset, int width, int height) {
  if (offset == vec2(0.0f)) return projection;
  const vec3 shift(-2.0f * offset.x / float(width), -2.0f * offset.y / float(height), 0.0f);
  return glm::translate(glm::mat4(1.0f), shift) * projection;
}

}  // namespace

void load_gl(GlProcLoader get_proc_address) {
  const int version = gladLoadGL(reinterpret_cast<GLADloadfunc>(get_proc_address));
  if (version == 0) throw std::runtime_error("could not load OpenGL entry points");
  if (GLAD_VERSION_MAJOR(version) * 10 + GLAD_VERSION_MINOR(version) < 33) {
    throw std::runtime_error("OpenGL 3.3 core needed, the context offers " +
                             std::to_string(GLAD_VERSION_MAJOR(version)) + "." +
                             std::to_string(GLAD_VERSION_MINOR(version)));
  }
}

Renderer::Renderer(std::string shader_directory) : shader_directory_(std::move(shader_directory)) {
  // Compile the most common variant now, so shader errors surface here.
  scene_program({"TERM 0"});
  shadow_program_ = ShaderProgram::build(shader_directory_, "shadow.vert", "shadow.frag");
  tonemap_program_ = ShaderProgram::build(shader_directory_, "fullscreen.vert", "tonemap.frag");
  accumulate_program_ =
      ShaderProgram::build(shader_directory_, "fullscreen.vert", "accumulate.frag");
  accumulate_program_.use();
  accumulate_program_.set("u_frame_radiance", int(kUnitFrame));
  flat_program_ = ShaderProgram::build(shader_directory_, "scene.vert", "flat.frag");
  depth_program_ = ShaderProgram::build(shader_directory_, "scene.vert", "depth.frag");
  for (int textured = 0; textured < 2; ++textured) {
    sky_programs_[textured] = ShaderProgram::build(shader_directory_, "fullscreen.vert", "sky.frag",
                                                   {"HAS_SKY_TEXTURE " + std::to_string(textured)});
    sky_programs_[textured].use();
    sky_programs_[textured].set("u_sky_texture", int(kUnitSky));
  }
  empty_vertex_array_ = gl::make_vertex_array();
  tonemap_program_.use();
  tonemap_program_.set("u_radiance", int(kUnitRadiance));
  glUseProgram(0);
  gl::check_errors("building shaders from " + shader_path(shader_directory_, ""));
}

Renderer::~Renderer() = default;

const ShaderProgram& Renderer::scene_program(const std::vector<std::string>& defines) {
  std::string key;
  for (const auto& define : defines) key += define + ";";
  auto it = scene_programs_.find(key);
  if (it != scene_programs_.end()) return it->second;
  std::vector<std::string> all = {"SHADOW_LOOKUP"};
  // Every feature define is present (0 unless listed), so `#if NAME` never sees an undefined.
  for (const char* name :
       {"USE_DIRECT", "USE_SHADOWS", "USE_CAUSTICS", "USE_RADIOSITY", "SPECULAR", "BUMP_KIND",
        "HAS_NORMALS", "HAS_REFLECTANCE_TEXTURE", "HAS_LIGHTMAP", "HAS_DIRECTIONAL", "HAS_VERTEX_RADIANCE",
        "HAS_SOFT_DIRECTIONAL",
        "HAS_PATCHES", "HAS_ENVIRONMENT", "HAS_PLANAR", "HAS_LAMPS", "STOCHASTIC", "PROBE_LIT",
        "ALPHA_CUT"}) {
    bool listed = false;
    for (const auto& define : defines) listed |= define.rfind(std::string(name) + " ", 0) == 0;
    if (!listed) all.push_back(std::string(name) + " 0");
  }
  all.insert(all.end(), defines.begin(), defines.end());
  ShaderProgram program = ShaderProgram::build(shader_directory_, "scene.vert", "scene.frag", all);
  program.use();
  program.set("u_light_triangles", int(kUnitLightTriangles));
  program.set("u_shadow_points", int(kUnitShadowPoints));
  program.set("u_shadow_maps", int(kUnitShadowMaps));
  program.set("u_reflectance_texture", int(kUnitReflectance));
  program.set("u_bump_texture", int(kUnitBump));
  program.set("u_lightmap", int(kUnitLightmap));
  program.set("u_lightmap_l1_x", int(kUnitLightmapL1X));
  program.set("u_lightmap_l1_y", int(kUnitLightmapL1Y));
  program.set("u_lightmap_l1_z", int(kUnitLightmapL1Z));
  program.set("u_triangle_patch", int(kUnitPatches));
  program.set("u_environment", int(kUnitEnvironment));
  program.set("u_environment_self", int(kUnitEnvironmentSelf));
  program.set("u_planar_reflection", int(kUnitPlanar));
  program.set("u_light_outlines", int(kUnitLightOutlines));
  program.set("u_soft_light", int(kUnitSoftLight));
  program.set("u_soft_light_l1_x", int(kUnitSoftLightL1X));
  program.set("u_soft_light_l1_y", int(kUnitSoftLightL1Y));
  program.set("u_soft_light_l1_z", int(kUnitSoftLightL1Z));
  program.set("u_lamp_shadow_maps", int(kUnitLampShadowMaps));
  program.set("u_light_data", int(kUnitLightData));
  program.set("u_lamp_data", int(kUnitLampData));
  program.set("u_light_list", int(kUnitLightList));
  return scene_programs_.emplace(key, std::move(program)).first->second;
}

void Renderer::set_scene(const Scene& scene, const BakeResult* bake,
                         const ShadowSettings& shadows) {
  scene_.reset();
  shadows_ = ShadowMaps();
  lamp_shadows_ = LampShadowMaps();
  environment_ = EnvironmentCubes();
  scene_ = std::make_unique<GpuScene>(scene, bake);
  build_alpha_programs();
  start_culling();
  // Planar mirrors and glossy plates up to kMaxPlanarRoughness, one pass per plane (coplanar
  // meshes share it); rougher plates read the environment capture.
  planar_.clear();
  const float plane_tolerance = 1e-4f * std::max(scene_->bounds().diagonal(), 1e-3f);
  for (size_t m = 0; m < scene_->meshes().size(); ++m) {
    const GpuMesh& mesh = scene_->meshes()[m];
    const Material& material = scene_->scene().materials[size_t(mesh.material)];
    const bool reflects =
        material.kind == MaterialKind::mirror ||
        (material.kind == MaterialKind::glossy && material.roughness <= kMaxPlanarRoughness);
    if (!mesh.planar || !reflects) continue;
    auto same_plane = [&](const PlanarReflection& p) {
      return glm::dot(vec3(p.plane), vec3(mesh.plane)) > 0.9999f &&
             std::abs(p.plane.w - mesh.plane.w) <= plane_tolerance;
    };
    auto group = std::find_if(planar_.begin(), planar_.end(), same_plane);
    if (group == planar_.end()) {
      group = planar_.emplace(planar_.end());
      group->plane = mesh.plane;
    }
    group->meshes.push_back(int(m));
    group->bounds.extend(mesh.bounds.min);
    group->bounds.extend(mesh.bounds.max);
  }
  // ~12 ms a table: once per roughness, however many materials share it.
  glossy_albedo_.assign(scene.materials.size(), {});
  std::map<float, size_t> tabled;  // roughness -> the first material with it
  for (size_t k = 0; k < scene.materials.size(); ++k) {
    if (scene.materials[k].kind != MaterialKind::glossy) continue;
    const float roughness = scene.materials[k].roughness;
    if (const auto same = tabled.find(roughness); same != tabled.end()) {
      glossy_albedo_[k] = glossy_albedo_[same->second];
      continue;
    }
    tabled.emplace(roughness, k);
    for (int i = 0; i < kGlossyAlbedoEntries; ++i)
      glossy_albedo_[k].push_back(
          glossy_albedo(roughness, (float(i) + 0.5f) / float(kGlossyAlbedoEntries)));
  }
  const auto start = std::chrono::steady_clock::now();
  all_lights_ = LightLists::all_lights(*scene_);
  const int cubes =
      shadow_samples_per_light(shadows, scene_->lights().lights.size(), max_shadow_layers()) *
      int(scene_->lights().lights.size());
  const int lamps = std::min(int(scene.lights.size()), kMaxShadowedLamps);
  stats_.shadow_resolution = shadows.resolution > 0
                                 ? ShadowResolution{shadows.resolution, "", 0.0f, 0.0f, false}
                                 : automatic_shadow_resolution(scene, scene_->lights().lights,
                                                               6 * (cubes + lamps));
  build_shadow_cubes(with_resolution(shadows), true);
  lamp_shadows_ = LampShadowMaps(*scene_, shadow_programs(), with_resolution(shadows));
  stats_.shadow_build_seconds = seconds_since(start);
  stats_.lamp_shadow_layers = lamp_shadows_.layer_count();
  stats_.lamps_unshadowed = lamp_shadows_.unshadowed_count();
  light_table_ = make_light_table(*scene_, shadows_, lamp_shadows_);
  ++scene_generation_;
  const auto env_start = std::chrono::steady_clock::now();
  build_environment();
  stats_.environment_seconds = seconds_since(env_start);
}

void Renderer::set_shadow_points(const ShadowSettings& shadows) {
  if (!scene_) throw std::logic_error("Renderer::set_shadow_points before set_scene");
  const auto start = std::chrono::steady_clock::now();
  build_shadow_cubes(with_resolution(shadows), false);
  stats_.shadow_build_seconds = seconds_since(start);
  light_table_ = make_light_table(*scene_, shadows_, lamp_shadows_);
  ++scene_generation_;
}

ShadowSettings Renderer::with_resolution(ShadowSettings shadows) const {
  if (shadows.resolution <= 0) shadows.resolution = stats_.shadow_resolution.resolution;
  return shadows;
}

void Renderer::build_shadow_cubes(const ShadowSettings& shadows, bool fresh) {
  std::optional<LightLists> lists;
  if (culling_.light_lists) lists.emplace(*scene_);
  if (fresh) {
    shadows_ = ShadowMaps(*scene_, shadow_programs(), shadows, lists ? &*lists : nullptr);
  } else {
    shadows_.rebuild(*scene_, shadow_programs(), shadows, lists ? &*lists : nullptr);
  }
  stats_.shadow_cubes = shadows_.cube_count();
  stats_.shadow_cubes_drawn = shadows_.draw_counts();
  light_lists_ = lists ? std::move(*lists) : LightLists::all_lights(*scene_);
  stats_.light_lists_seconds = light_lists_.finish_seconds();
  stats_.light_list_queries = light_lists_.queries();
  stats_.lights_per_chunk_mean = light_lists_.mean_lights();
  stats_.lights_per_chunk_max = light_lists_.max_lights();
}

namespace {

// The same triangles, corners and normals: the lists (made from them) still hold.
bool same_geometry(const Scene& a, const Scene& b) {
  if (a.meshes.size() != b.meshes.size()) return false;
  for (size_t m = 0; m < a.meshes.size(); ++m) {
    const Mesh &x = a.meshes[m], &y = b.meshes[m];
    if (x.positions != y.positions || x.triangles != y.triangles || x.normals != y.normals)
      return false;
    // What decides whether and how a mesh shades the direct light, and which lights exist.
    const Material &p = a.materials[size_t(x.material)], &q = b.materials[size_t(y.material)];
    if (p.kind != q.kind || p.is_emitter() != q.is_emitter() ||
        p.two_sided_emission != q.two_sided_emission || p.bump != q.bump ||
        (p.bump_texture >= 0) != (q.bump_texture >= 0))
      return false;
  }
  return true;
}

}  // namespace

void Renderer::build_alpha_programs() {
  if (!any_alpha_cut(*scene_) || shadow_alpha_program_) return;
  shadow_alpha_program_ =
      ShaderProgram::build(shader_directory_, "shadow.vert", "shadow.frag", {"ALPHA_CUT 1"});
  depth_alpha_program_ =
      ShaderProgram::build(shader_directory_, "scene.vert", "depth.frag", {"ALPHA_CUT 1"});
}

DepthPrograms Renderer::shadow_programs() const {
  const bool cut = scene_ && any_alpha_cut(*scene_);
  return {&shadow_program_, cut ? &shadow_alpha_program_ : nullptr};
}

DepthPrograms Renderer::depth_programs() const {
  const bool cut = scene_ && any_alpha_cut(*scene_);
  return {&depth_program_, cut ? &depth_alpha_program_ : nullptr};
}

void Renderer::start_culling() {
  scene_->set_culling(culling_.frustum);
  scene_->set_occlusion_culling(culling_.shadow_occlusion);
  camera_culler_ = std::make_unique<OcclusionCuller>(*scene_, OcclusionCuller::Members::all);
  camera_schedule_.reset();
}

void Renderer::update_scene(const Scene& scene, const BakeResult* bake) {
  if (!scene_) return set_scene(scene, bake);
  environment_ = EnvironmentCubes();
  std::unique_ptr<GpuScene> old = std::move(scene_);
  scene_ = std::make_unique<GpuScene>(scene, bake);
  build_alpha_programs();
  // Other meshes (a bake's radiosity meshes): every light, which is exact, until set_scene.
  all_lights_ = LightLists::all_lights(*scene_);
  if (!same_geometry(old->scene(), scene_->scene())) light_lists_ = LightLists::all_lights(*scene_);
  old.reset();
  start_culling();
  light_table_ = make_light_table(*scene_, shadows_, lamp_shadows_);
  ++scene_generation_;
  build_environment();
}

void Renderer::ensure_target(int width, int height) {
  if (target_ && width == width_ && height == height_) return;
  width_ = width;
  height_ = height;
  make_target(width, height, true, target_, target_colour_, target_depth_);
  gl::Texture no_depth;
  make_target(width, height, false, accumulation_, accumulation_colour_, no_depth);
  accumulated_ = 0;
  shows_accumulation_ = false;
}

void Renderer::set_culling(Culling culling) {
  if (!(culling == culling_)) camera_schedule_.reset();  // what the queries won no longer holds
  culling_ = culling;
  if (scene_) {
    scene_->set_culling(culling.frustum);
    scene_->set_occlusion_culling(culling.shadow_occlusion);
  }
}

DrawCounts Renderer::draw_scene(const glm::mat4& view_projection, vec3 eye,
                                const RenderSettings& settings, const std::vector<int>& skip,
                                bool capture, glm::vec4 clip_plane, bool planar,
                                const std::vector<char>* drawn) {
  const GpuScene& scene = *scene_;
  Frustum frustum(view_projection);
  if (clip_plane != glm::vec4(0.0f)) frustum.add_plane(clip_plane);  // a mirror pass
  const DetailView detail = capture ? DetailView()
                                    : make_detail_view(view_projection, eye, height_,
                                                       settings.detail_pixels);
  DrawCounts counts;
  const GpuLights& lights = scene.lights();
  const bool stochastic = settings.direct_mode == DirectMode::stochastic && !capture;
  const bool environment = !capture && !environment_.empty();
  // Per-frame uniforms, set whenever a different variant comes into use.
  auto set_frame_uniforms = [&](const ShaderProgram& program) {
    program.use();
    program.set("u_view_projection", view_projection);
    program.set("u_camera_position", eye);
    program.set("u_ambient", settings.ambient ? settings.ambient_radiance : vec3(0.0f));
    program.set("u_bump_lod_bias", settings.bump_full_resolution ? -64.0f : -1.0f);
    program.set("u_light_count", light_table_.light_count);
    program.set("u_lamp_count", light_table_.lamp_count);
    glUniform1ui(program.location("u_frame"), GLuint(accumulated_));
    program.set("u_lamp_shadow_resolution", lamp_shadows_.resolution());
    program.set("u_shadow_resolution", shadows_.resolution());
    program.set("u_shadow_near", shadows_.near_plane());
    program.set("u_shadow_far", shadows_.far_plane());
    program.set("u_environment_reach", std::max(scene.bounds().diagonal(), 1e-3f));
    program.set("u_planar_levels", float(std::log2(float(std::max(width_, height_)))));
    glUniform4f(program.location("u_clip_plane"), clip_plane.x, clip_plane.y, clip_plane.z,
                clip_plane.w);
  };
  bind(kUnitLightTriangles, GL_TEXTURE_BUFFER, lights.triangles.texture.get());
  bind(kUnitLightOutlines, GL_TEXTURE_BUFFER, lights.outlines.texture.get());
  bind(kUnitLightData, GL_TEXTURE_BUFFER, light_table_.lights.texture.get());
  const LightLists& lists = culling_.light_lists ? light_lists_ : all_lights_;
  bind(kUnitLightList, GL_TEXTURE_BUFFER, lists.texture());
  bind(kUnitLampData, GL_TEXTURE_BUFFER, light_table_.lamps.texture.get());
  bind(kUnitShadowPoints, GL_TEXTURE_BUFFER, shadows_.points_texture());
  bind(kUnitShadowMaps, GL_TEXTURE_2D_ARRAY, shadows_.depth_array());
  bind(kUnitLampShadowMaps, GL_TEXTURE_2D_ARRAY, lamp_shadows_.depth_array());
  bind(kUnitLightmap, GL_TEXTURE_2D, scene.lightmap());
  bind(kUnitLightmapL1X, GL_TEXTURE_2D, scene.lightmap_l1(0));
  bind(kUnitLightmapL1Y, GL_TEXTURE_2D, scene.lightmap_l1(1));
  bind(kUnitLightmapL1Z, GL_TEXTURE_2D, scene.lightmap_l1(2));
  bind(kUnitSoftLight, GL_TEXTURE_2D, scene.soft_light_map());
  bind(kUnitSoftLightL1X, GL_TEXTURE_2D, scene.soft_light_l1(0));
  bind(kUnitSoftLightL1Y, GL_TEXTURE_2D, scene.soft_light_l1(1));
  bind(kUnitSoftLightL1Z, GL_TEXTURE_2D, scene.soft_light_l1(2));

  const ShaderProgram* current = nullptr;
  for (size_t m = 0; m < scene.meshes().size(); ++m) {
    if (std::find(skip.begin(), skip.end(), int(m)) != skip.end()) continue;
    const GpuMesh& mesh = scene.meshes()[m];
    if (mesh.index_count == 0) continue;
    if (drawn && !(*drawn)[m]) {  // hidden behind the pre-pass's depth
      scene.count_skipped(m, counts);
      continue;
    }
    // Before choosing the shader: a big level's meshes are mostly out of view.
    if (scene.culled(m, frustum, counts)) continue;
    const Material& material = scene.scene().materials[size_t(mesh.material)];
    const GLuint reflectance_texture = scene.texture(material.reflectance_texture);
    const GLuint bump_texture = scene.texture(material.bump_texture);
    GLuint reflection = 0;
    if (planar) {
      for (const PlanarReflection& p : planar_) {
        if (p.visible && std::find(p.meshes.begin(), p.meshes.end(), int(m)) != p.meshes.end())
          reflection = p.colour.get();
      }
    }
    auto flag = [](const char* name, bool on) { return std::string(name) + (on ? " 1" : " 0"); };
    const std::vector<std::string> defines = {
        "TERM " + std::to_string(int(settings.term)),
        flag("USE_DIRECT",
             (settings.direct && settings.term != Term::baked && !scene.lightmap_holds_direct()) ||
                 settings.term == Term::direct),
        flag("USE_SHADOWS", settings.shadows),
        flag("USE_CAUSTICS",
             settings.caustics || settings.term == Term::caustic || settings.term == Term::baked),
        flag("USE_RADIOSITY", settings.radiosity || settings.term == Term::radiosity ||
                                  settings.term == Term::baked),
        flag("SPECULAR", !material.is_diffuse()),
        "BUMP_KIND " + std::to_string(bump_texture ? int(material.bump) : 0),
        flag("HAS_NORMALS", mesh.has_normals),
        flag("HAS_REFLECTANCE_TEXTURE", reflectance_texture != 0),
        flag("HAS_LIGHTMAP", mesh.has_lightmap && scene.lightmap()),
        flag("HAS_DIRECTIONAL", settings.directional && mesh.has_lightmap && scene.lightmap() &&
                                    scene.lightmap_l1(0) != 0),
        flag("HAS_VERTEX_RADIANCE", mesh.has_vertex_radiance),
        flag("HAS_SOFT_MAP",
             mesh.has_lightmap && mesh.has_vertex_radiance && scene.soft_light_map() != 0),
        // Bumped surfaces only: elsewhere n = n0 and the decode is the map (its bits, as HQ's).
        flag("HAS_SOFT_DIRECTIONAL", settings.directional && bump_texture != 0 &&
                                         mesh.has_lightmap && mesh.has_vertex_radiance &&
                                         scene.soft_light_l1(0) != 0),
        flag("HAS_PATCHES", mesh.has_patches),
        flag("PROBE_LIT", mesh.probe_lit),
        flag("HAS_ENVIRONMENT", environment),
        flag("HAS_PLANAR", reflection != 0),
        flag("HAS_LAMPS", !scene.scene().lights.empty()),
        flag("STOCHASTIC", stochastic),
        flag("ALPHA_CUT", alpha_cut(scene, m))};
    const ShaderProgram& program = scene_program(defines);
    if (&program != current) {
      set_frame_uniforms(program);
      current = &program;
    }
    program.set("u_kind", int(material.kind));
    program.set("u_reflectance", material.reflectance);
    program.set("u_emission", material.emission);
    program.set("u_two_sided_emission", int(material.two_sided_emission));
    program.set("u_ior", material.ior);
    program.set("u_roughness", material.roughness);
    if (!glossy_albedo_[size_t(mesh.material)].empty())
      program.set("u_glossy_albedo", glossy_albedo_[size_t(mesh.material)].data(),
                  kGlossyAlbedoEntries);
    program.set("u_bump_scale", material.bump_scale);
    if (mesh.probe_lit) program.set("u_probe_sh", mesh.probe_sh.data(), kShCoefficients);
    bind(kUnitReflectance, GL_TEXTURE_2D, reflectance_texture);
    bind(kUnitBump, GL_TEXTURE_2D, bump_texture);
    bind(kUnitPatches, GL_TEXTURE_BUFFER, mesh.triangle_patch.texture.get());
    bind(kUnitPlanar, GL_TEXTURE_2D, reflection);
    if (alpha_cut(scene, m)) set_alpha_cut(program, scene, m);
    const EnvironmentCube* cube = environment ? environment_.cube_for(int(m)) : nullptr;
    bind(kUnitEnvironment, GL_TEXTURE_CUBE_MAP, cube ? cube->texture.get() : 0);
    program.set("u_environment_centre", cube ? cube->centre : vec3(0.0f));
    program.set("u_environment_parallax", cube && cube->parallax ? 1.0f : 0.0f);
    program.set("u_environment_levels", cube ? std::log2(float(cube->texels)) : 0.0f);
    bind(kUnitEnvironmentSelf, GL_TEXTURE_CUBE_MAP, cube ? cube->self.get() : 0);
    program.set("u_environment_glass", cube && cube->self ? 1.0f : 0.0f);
    program.set("u_environment_size", cube ? cube->size : 0.0f);
    scene.draw_mesh(m, frustum, counts, detail, program.location("u_first_triangle"),
                    &lists.ranges(m, settings.shadows), program.location("u_light_range"),
                    program.location("u_detail_lift"));
  }
  glBindVertexArray(0);
  glActiveTexture(GL_TEXTURE0);
  return counts;
}

// The environment cubes (viewer/environment_cubes.h), each face drawn with the full image
// but the ambient term and without the environment itself.
void Renderer::build_environment() {
  RenderSettings settings;
  settings.ambient = false;
  environment_ = EnvironmentCubes(*scene_, [&](const glm::mat4& view_projection, vec3 eye,
                                               const std::vector<int>& skip, bool normals) {
    RenderSettings capture = settings;
    if (normals) capture.term = Term::normals;  // draw_sky draws nothing then
    draw_scene(view_projection, eye, capture, skip, true);
    draw_sky(view_projection, capture);
  });
  stats_.environment_object_cubes = environment_.object_cube_count();
}

void Renderer::render(const ViewCamera& camera, int width, int height,
                      const RenderSettings& settings, vec2 pixel_offset) {
  if (!scene_) throw std::logic_error("Renderer::render before set_scene");
  ensure_target(width, height);
  pixel_offset_ = pixel_offset;
  const glm::mat4 view_projection =
      offset_projection(camera.projection(float(width) / float(height), scene_->bounds()),
                        pixel_offset, width, height) *
      camera.view();
  // A still view: the same camera, settings and scene as the frame before.
  const AccumulationKey key{view_projection,      camera.position,       settings.term,
                            settings.direct,      settings.shadows,      settings.caustics,
                            settings.radiosity,   settings.ambient,      settings.ambient_radiance,
                            settings.direct_mode, settings.refine_bands,
                            settings.planar_reflections, settings.bump_full_resolution,
                            settings.detail_pixels,      scene_generation_};
  const bool stochastic = settings.direct_mode == DirectMode::stochastic;
  if (!stochastic || !shows_accumulation_ || !(key == accumulation_key_)) accumulated_ = 0;
  accumulation_key_ = key;
  const int bands = std::max(0, settings.refine_bands);
  if (stochastic && bands > 0 && accumulated_ > bands) return;  // exact already
  if (stochastic && bands > 0 && accumulated_ > 0) return refine_band(camera, settings);

  render_planar_reflections(camera, width, height, settings);
  draw_frame(view_projection, camera.position, settings);
  shows_accumulation_ = stochastic;
  if (stochastic) accumulate();
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  gl::check_errors("rendering a frame");
}

void Renderer::draw_frame(const glm::mat4& view_projection, vec3 eye,
                          const RenderSettings& settings) {
  glBindFramebuffer(GL_FRAMEBUFFER, target_.get());
  glViewport(0, 0, width_, height_);
  glClearColor(0, 0, 0, 1);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  glDisable(GL_CULL_FACE);
  glDisable(GL_BLEND);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
  const bool occlusion = camera_queries();
  if (culling_.depth_prepass)
    draw_depth(view_projection, eye, occlusion,
               make_detail_view(view_projection, eye, height_, settings.detail_pixels));
  stats_.view = draw_scene(view_projection, eye, settings, {}, false, glm::vec4(0.0f), true,
                           occlusion ? &camera_drawn_ : nullptr);
  glDisable(GL_STENCIL_TEST);
  glDepthFunc(GL_LESS);
  draw_sky(view_projection, settings);
}

bool Renderer::camera_queries() {
  stats_.camera_occlusion_queries = 0;
  stats_.camera_occlusion_queried = false;
  if (!culling_.depth_prepass || !culling_.camera_occlusion) return false;
  if (!culling_.camera_occlusion_every_frame && !camera_schedule_.query()) {
    camera_schedule_.frame_done(false, 0.0, 0.0);
    return false;
  }
  stats_.camera_occlusion_queried = true;
  return true;
}

void Renderer::draw_depth(const glm::mat4& view_projection, vec3 eye, bool occlusion,
                          const DetailView& detail) {
  glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
  glEnable(GL_STENCIL_TEST);
  glStencilFunc(GL_ALWAYS, 1, 0xff);
  glStencilOp(GL_KEEP, GL_KEEP, GL_REPLACE);
  const DepthPrograms programs = depth_programs();
  if (programs.alpha_cut) {
    programs.alpha_cut->use();
    glUniform1ui(programs.alpha_cut->location("u_frame"), GLuint(accumulated_));
  }
  programs.set("u_view_projection", view_projection);
  const Frustum frustum(view_projection);
  DrawCounts counts;
  if (occlusion) {
    // GL_LEQUAL: a skipped box lies strictly behind the depth, so none of its meshes'
    // fragments could pass the shading pass's GL_EQUAL either.
    camera_culler_->set_occluders_first(culling_.occluders_first);
    camera_culler_->draw(*scene_, frustum, eye, near_reach(view_projection, eye), GL_LEQUAL,
                         counts, &camera_drawn_, detail);
    stats_.camera_occlusion_queries = camera_culler_->queries();
    camera_schedule_.frame_done(true, double(camera_culler_->triangles_hidden()),
                                double(camera_culler_->triangles_in_view()));
  } else {
    for (size_t m = 0; m < scene_->meshes().size(); ++m) {
      if (programs.alpha_cut && alpha_cut(*scene_, m)) continue;
      if (!scene_->culled(m, frustum, counts)) scene_->draw_mesh(m, frustum, counts, detail);
    }
  }
  draw_alpha_cut(*scene_, programs, frustum, counts, false, occlusion ? &camera_drawn_ : nullptr,
                 detail);
  glBindVertexArray(0);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  // GL_LESS without the pre-pass keeps, per pixel, the first fragment drawn at the nearest
  // depth. Here: fragments at exactly that depth (EQUAL), the first of them only (stencil
  // 1 -> 2), and none where nothing was drawn (stencil 0), so the bits are the same.
  glDepthFunc(GL_EQUAL);
  glStencilFunc(GL_EQUAL, 1, 0xff);
  glStencilOp(GL_KEEP, GL_KEEP, GL_INCR);
}

// Band b (1-based, from the bottom row up) of the full evaluation, drawn with the scissor
// (only its fragments are shaded) and copied over the estimate: the same shader variant and
// inputs as DirectMode::full, so the bits are the full frame's.
void Renderer::refine_band(const ViewCamera& camera, const RenderSettings& settings) {
  RenderSettings full = settings;
  full.direct_mode = DirectMode::full;
  const int bands = settings.refine_bands;
  if (accumulated_ == 1) render_planar_reflections(camera, width_, height_, full);
  const int y0 = height_ * (accumulated_ - 1) / bands, y1 = height_ * accumulated_ / bands;
  glEnable(GL_SCISSOR_TEST);
  glScissor(0, y0, width_, y1 - y0);
  draw_frame(accumulation_key_.view_projection, camera.position, full);
  const int seen = accumulated_;
  accumulated_ = 0;  // a copy, not a blend
  accumulate();
  accumulated_ = seen + 1;
  glDisable(GL_SCISSOR_TEST);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  gl::check_errors("refining a still frame");
}

// The running mean of the still camera's frames: mean_n+1 = mean_n + (frame - mean_n) / (n+1),
// as a blend with constant alpha 1 / (n + 1) (the first frame is copied).
void Renderer::accumulate() {
  glBindFramebuffer(GL_FRAMEBUFFER, accumulation_.get());
  glViewport(0, 0, width_, height_);
  glDisable(GL_DEPTH_TEST);
  if (accumulated_ > 0) {
    glEnable(GL_BLEND);
    glBlendColor(0.0f, 0.0f, 0.0f, 1.0f / float(accumulated_ + 1));
    glBlendFunc(GL_CONSTANT_ALPHA, GL_ONE_MINUS_CONSTANT_ALPHA);
  }
  accumulate_program_.use();
  bind(kUnitFrame, GL_TEXTURE_2D, target_colour_.get());
  glBindVertexArray(empty_vertex_array_.get());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glActiveTexture(GL_TEXTURE0);
  glDisable(GL_BLEND);
  glEnable(GL_DEPTH_TEST);
  ++accumulated_;
}

// A full-screen pass at the far plane (shaders/sky.frag writes depth 1), so it fills only the
// pixels no surface covered. Only the outputs that show emitted light show the sky.
void Renderer::draw_sky(const glm::mat4& view_projection, const RenderSettings& settings) {
  const std::optional<Sky>& sky = scene_->scene().sky;
  if (!sky || (settings.term != Term::all && settings.term != Term::baked)) return;
  const GLuint texture = scene_->texture(sky->texture);
  const ShaderProgram& program = sky_programs_[texture != 0 ? 1 : 0];
  program.use();
  program.set("u_inverse_view_projection", glm::inverse(view_projection));
  program.set("u_sky_radiance", sky->radiance);
  bind(kUnitSky, GL_TEXTURE_2D, texture);
  glDepthFunc(GL_LEQUAL);
  glDepthMask(GL_FALSE);
  glDisable(GL_CLIP_DISTANCE0);
  glBindVertexArray(empty_vertex_array_.get());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glActiveTexture(GL_TEXTURE0);
  glDepthMask(GL_TRUE);
  glDepthFunc(GL_LESS);
}

// Planar mirrors, exactly: the camera's view of the scene reflected about the mirror's plane
// (view-projection times the reflection matrix, so pixels correspond one to one), clipped to
// what lies in front of the plane, drawn with the full shading (lighting at the true
// positions). Glossy plates read a blurrier mip level of it. One extra scene pass per plane
// (coplanar mirrors share it) that faces the camera, at most kMaxPlanarPasses per frame: the
// planes whose meshes look largest (bounding-box diagonal over distance); the others read the
// environment capture this frame.
void Renderer::render_planar_reflections(const ViewCamera& camera, int width, int height,
                                         const RenderSettings& settings) {
  std::vector<std::pair<float, PlanarReflection*>> candidates;
  for (PlanarReflection& p : planar_) {
    p.visible = false;
    if (!settings.planar_reflections) continue;
    if (glm::dot(vec3(p.plane), camera.position) + p.plane.w <= 0.0f) continue;
    const vec3 centre = 0.5f * (p.bounds.min + p.bounds.max);
    const float distance = std::max(glm::length(centre - camera.position), 1e-6f);
    candidates.emplace_back(p.bounds.diagonal() / distance, &p);
  }
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const auto& a, const auto& b) { return a.first > b.first; });
  if (candidates.size() > size_t(kMaxPlanarPasses)) candidates.resize(size_t(kMaxPlanarPasses));
  stats_.planar_passes = int(candidates.size());
  for (auto& candidate : candidates) {
    PlanarReflection& p = *candidate.second;
    p.visible = true;
    const vec3 n(p.plane);
    const float d = p.plane.w;
    if (!p.framebuffer || p.width != width || p.height != height) {
      p.width = width;
      p.height = height;
      p.colour = gl::make_texture();
      glBindTexture(GL_TEXTURE_2D, p.colour.get());
      glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA16F, width, height, 0, GL_RGBA, GL_FLOAT, nullptr);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
      glGenerateMipmap(GL_TEXTURE_2D);
      p.depth = gl::make_texture();
      glBindTexture(GL_TEXTURE_2D, p.depth.get());
      glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT32F, width, height, 0, GL_DEPTH_COMPONENT,
                   GL_FLOAT, nullptr);
      p.framebuffer = gl::make_framebuffer();
      glBindFramebuffer(GL_FRAMEBUFFER, p.framebuffer.get());
      glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, p.colour.get(),
                             0);
      glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, p.depth.get(), 0);
    }
    // x' = x - 2 (n.x + d) n
    glm::mat4 reflection(1.0f);
    for (int c = 0; c < 3; ++c) {
      for (int r = 0; r < 3; ++r) reflection[c][r] -= 2.0f * n[c] * n[r];
      reflection[3][c] = -2.0f * d * n[c];
    }
    Bounds bounds = scene_->bounds();
    const Bounds original = bounds;
    for (int corner = 0; corner < 8; ++corner) {
      const vec3 q{(corner & 1) ? original.max.x : original.min.x,
                   (corner & 2) ? original.max.y : original.min.y,
                   (corner & 4) ? original.max.z : original.min.z};
      bounds.extend(vec3(reflection * glm::vec4(q, 1.0f)));
    }
    const glm::mat4 view_projection =
        offset_projection(camera.projection(float(width) / float(height), bounds), pixel_offset_,
                          width, height) *
        camera.view() * reflection;
    glBindFramebuffer(GL_FRAMEBUFFER, p.framebuffer.get());
    glViewport(0, 0, width, height);
    glClearColor(0, 0, 0, 1);
    glEnable(GL_DEPTH_TEST);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_CLIP_DISTANCE0);
    glFrontFace(GL_CW);  // the reflection flips the winding; keep gl_FrontFacing meaning front
    const vec3 mirrored_eye = vec3(reflection * glm::vec4(camera.position, 1.0f));
    draw_scene(view_projection, mirrored_eye, settings, p.meshes, false, p.plane, false);
    glFrontFace(GL_CCW);
    glDisable(GL_CLIP_DISTANCE0);
    draw_sky(view_projection, settings);
    glBindTexture(GL_TEXTURE_2D, p.colour.get());
    glGenerateMipmap(GL_TEXTURE_2D);
    glBindTexture(GL_TEXTURE_2D, 0);
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

void Renderer::render_flat(const ViewCamera& camera, int width, int height, float detail_pixels) {
  if (!scene_) throw std::logic_error("Renderer::render_flat before set_scene");
  ensure_target(width, height);
  shows_accumulation_ = false;
  glBindFramebuffer(GL_FRAMEBUFFER, target_.get());
  glViewport(0, 0, width, height);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
  const glm::mat4 view_projection =
      camera.projection(float(width) / float(height), scene_->bounds()) * camera.view();
  // With camera occlusion, a pre-pass finds what shows (the same bits, as in draw_frame).
  const bool occlusion = camera_queries();
  const DetailView detail =
      make_detail_view(view_projection, camera.position, height, detail_pixels);
  if (occlusion) draw_depth(view_projection, camera.position, true, detail);
  flat_program_.use();
  flat_program_.set("u_view_projection", view_projection);
  const Frustum frustum(view_projection);
  stats_.view = DrawCounts();
  for (size_t m = 0; m < scene_->meshes().size(); ++m) {
    if (occlusion && !camera_drawn_[m]) {
      scene_->count_skipped(m, stats_.view);
      continue;
    }
    if (scene_->culled(m, frustum, stats_.view)) continue;
    flat_program_.set("u_reflectance",
                      scene_->scene().materials[size_t(scene_->meshes()[m].material)].reflectance);
    scene_->draw_mesh(m, frustum, stats_.view, detail);
  }
  glBindVertexArray(0);
  glDisable(GL_STENCIL_TEST);
  glDepthFunc(GL_LESS);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

void Renderer::present(GLuint framebuffer, const ToneMap& tone, int output_width,
                       int output_height) {
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
  glViewport(0, 0, output_width > 0 ? output_width : width_,
             output_height > 0 ? output_height : height_);
  glDisable(GL_DEPTH_TEST);
  tonemap_program_.use();
  tonemap_program_.set("u_exposure", tone.exposure);
  tonemap_program_.set("u_curve", int(tone.curve));
  bind(kUnitRadiance, GL_TEXTURE_2D,
       shows_accumulation_ ? accumulation_colour_.get() : target_colour_.get());
  glBindVertexArray(empty_vertex_array_.get());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glActiveTexture(GL_TEXTURE0);
  glEnable(GL_DEPTH_TEST);
}

Image Renderer::read_radiance() const {
  Image image(width_, height_, 3);
  std::vector<float> rgba(size_t(width_) * size_t(height_) * 4);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, shows_accumulation_ ? accumulation_.get() : target_.get());
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width_, height_, GL_RGBA, GL_FLOAT, rgba.data());
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  for (int y = 0; y < height_; ++y) {
    const int row = height_ - 1 - y;  // GL rows go bottom up
    for (int x = 0; x < width_; ++x) {
      for (int c = 0; c < 3; ++c) {
        image.at(x, y, c) = rgba[(size_t(row) * size_t(width_) + size_t(x)) * 4 + size_t(c)];
      }
    }
  }
  return image;
}

std::vector<uint8_t> Renderer::read_display(int width, int height) {
  std::vector<uint8_t> rgb(size_t(width) * size_t(height) * 3);
  std::vector<uint8_t> flipped(rgb.size());
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, rgb.data());
  const size_t stride = size_t(width) * 3;
  for (int y = 0; y < height; ++y) {
    std::copy_n(rgb.begin() + std::ptrdiff_t(size_t(height - 1 - y) * stride), stride,
                flipped.begin() + std::ptrdiff_t(size_t(y) * stride));
  }
  return flipped;
}

}  // namespace lb
