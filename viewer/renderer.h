#pragma once
// The OpenGL renderer. It knows nothing about windows: a front end makes a GL 3.3 core
// context current, loads GL (load_gl), then draws with it. A frame goes to an RGBA32F
// radiance target (read back for EXR or tone mapped on the CPU), and present() tone maps it
// into any framebuffer, e.g. the window's.

#include <map>
#include <memory>
#include <string>

#include "bake/bake_result.h"
#include "bake/io/image_io.h"
#include "viewer/alpha_cut.h"
#include "viewer/environment_cubes.h"
#include "viewer/gpu_scene.h"
#include "viewer/lamp_shadow_maps.h"
#include "viewer/light_lists.h"
#include "viewer/light_table.h"
#include "viewer/occlusion_culler.h"
#include "viewer/occlusion_schedule.h"
#include "viewer/render_settings.h"
#include "viewer/shader_program.h"
#include "viewer/shadow_maps.h"
#include "viewer/shadow_resolution.h"
#include "viewer/view_camera.h"

namespace lb {

// Loads the GL entry points through `get_proc_address` (glfwGetProcAddress,
// OSMesaGetProcAddress, ...). Throws if the context is older than 3.3.
using GlProcLoader = void (*(*)(const char*))();
void load_gl(GlProcLoader get_proc_address);

struct FrameStats {
  double shadow_build_seconds = 0.0;
  double environment_seconds = 0.0;
  int environment_object_cubes = 0;  // curved specular objects with a cube of their own
  int shadow_cubes = 0;
  ShadowResolution shadow_resolution;  // the maps' size, and the caster that set it
  int lamp_shadow_layers = 0;
  int lamps_unshadowed = 0;  // lamps beyond kMaxShadowedLamps
  // The light lists as last built: their per-triangle checks and upload (s; their occlusion
  // queries run inside the shadow build), queries issued, lights a diffuse chunk keeps.
  double light_lists_seconds = 0.0;
  int light_list_queries = 0;
  double lights_per_chunk_mean = 0.0;
  int lights_per_chunk_max = 0;
  int planar_passes = 0;  // mirrored scene passes in the last render()
  // Culling (viewer/frustum.h): the last render()'s or render_flat()'s camera pass alone,
  // and the area lights' shadow cubes as last built.
  DrawCounts view;
  DrawCounts shadow_cubes_drawn;
  int camera_occlusion_queries = 0;  // box queries of the last camera pass (Culling)
  bool camera_occlusion_queried = false;  // whether that pass queried (its schedule)
};

// Planar reflection passes per frame, at most (the rest read the environment capture).
constexpr int kMaxPlanarPasses = 4;
// Glossy plates rougher than this never get one: their blur hides what the capture misses.
constexpr float kMaxPlanarRoughness = 0.5f;
// View cosines at which a glossy material's albedo is tabled for the shader (u_glossy_albedo).
constexpr int kGlossyAlbedoEntries = 16;

class Renderer {
 public:
  explicit Renderer(std::string shader_directory = default_shader_directory());
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Uploads the scene (with the bake's maps and radiosity meshes when `bake` is given) and
  // renders the shadow cubes and environment captures. Replaces any previous scene.
  void set_scene(const Scene& scene, const BakeResult* bake = nullptr,
                 const ShadowSettings& shadows = {});
  // Swaps in new baked terms or light colours for the same geometry and light shapes,
  // keeping the shadow cubes (cheap: no shadow pass).
  void update_scene(const Scene& scene, const BakeResult* bake);
  // Renders the area lights' shadow cubes again from `shadows` (another interleaved set of
  // points, render_snapshot), keeping everything else.
  void set_shadow_points(const ShadowSettings& shadows);
  bool has_scene() const { return bool(scene_); }
  // What the renderer leaves out (both on by default); images are the same bits either way,
  // off is the benchmark's yardstick. Set before set_scene to cover the shadow maps too.
  struct Culling {
    // Chunks outside a pass's frustum (viewer/frustum.h), in every pass.
    bool frustum = true;
    // The camera pass first draws depth alone, then shades only the fragment each pixel
    // keeps: hidden surfaces (the rooms behind a wall) cost no shading.
    bool depth_prepass = true;
    // The area lights' shadow cubes draw what their faces may see past the nearest meshes
    // (viewer/occlusion_culler.h): a room's walls hide the rest of a level.
    bool shadow_occlusion = true;
    // Each chunk shades only the area lights that can reach it (viewer/light_lists.h): the
    // same bits. Built with the shadow cubes when on at set_scene; off draws every light.
    bool light_lists = true;
    // The camera's depth pre-pass draws the nearest cluster of meshes, then only those whose
    // box shows a sample against the depth so far (viewer/occlusion_culler.h), and the shading
    // pass only what it drew: the walls hide the rest of a level. Needs depth_prepass (with
    // both, render_flat draws such a pre-pass too). The planar mirrors' passes and the
    // environment capture keep frustum culling alone.
    bool camera_occlusion = true;
    // Query in every camera pass. Off (the default), a pass queries only while the queries
    // hide enough (viewer/occlusion_schedule.h); the image is the same bits either way.
    bool camera_occlusion_every_frame = false;
    // Camera occlusion tests the occluders (walls, floors, ceilings: viewer/occlusion_culler.h)
    // one by one right after the nearest cluster, so from above a level its ceilings hide the
    // rooms; the same bits either way. Off: the clusters alone (the bench's yardstick).
    bool occluders_first = true;
    bool operator==(const Culling&) const = default;
  };
  void set_culling(Culling culling);
  const GpuScene& scene() const { return *scene_; }
  const FrameStats& stats() const { return stats_; }
  const LightLists& light_lists() const { return light_lists_; }

  // Draws linear radiance of the view into the internal width x height target. With
  // DirectMode::stochastic the frames of a still view (same camera, size, settings and
  // scene) accumulate, and present() and read_radiance() show the result: the running mean
  // of the frames, or with refine_bands > 0 the first frame's estimate replaced band by band
  // by the full evaluation (exact after refine_bands + 1 frames; later calls draw nothing).
  // Any change starts again. `pixel_offset` (pixels, x right, y up, within +-0.5) moves every
  // pixel's sample point off its centre: still images average such frames (render_snapshot).
  void render(const ViewCamera& camera, int width, int height, const RenderSettings& settings,
              vec2 pixel_offset = vec2(0.0f));
  // Still frames behind what the last render() showed (1 after a change; 0 in full mode).
  int accumulated_frames() const { return shows_accumulation_ ? accumulated_ : 0; }
  // Whether the image shown is the full evaluation (full mode, or stochastic refined).
  bool exact(const RenderSettings& settings) const {
    return !shows_accumulation_ ||
           (settings.refine_bands > 0 && accumulated_ > settings.refine_bands);
  }
  // The benchmark yardstick: the same geometry with one flat colour per material.
  void render_flat(const ViewCamera& camera, int width, int height, float detail_pixels = 0.0f);
  // Tone maps the last frame into `framebuffer` (0: the default one), at the frame's size or
  // scaled (nearest) to output_width x output_height when those are given.
  void present(GLuint framebuffer, const ToneMap& tone, int output_width = 0,
               int output_height = 0);
  // The last frame's radiance, RGB, top row first. Waits for the GPU.
  Image read_radiance() const;
  // 8-bit RGB of the currently bound read framebuffer (e.g. after present()), top row first.
  static std::vector<uint8_t> read_display(int width, int height);

 private:
  // The new scene_'s frustum and shadow-map culling as set, and a fresh camera culler.
  void start_culling();
  void ensure_target(int width, int height);
  // Draws every mesh but those in `skip` (a mirror does not see itself).
  // Returns what it drew.
  // `drawn` (one flag per mesh, optional): only the meshes flagged.
  DrawCounts draw_scene(const glm::mat4& view_projection, vec3 eye, const RenderSettings& settings,
                        const std::vector<int>& skip, bool capture,
                        glm::vec4 clip_plane = glm::vec4(0.0f), bool planar = false,
                        const std::vector<char>* drawn = nullptr);
  void build_environment();
  void accumulate();  // blends the frame in target_ into accumulation_
  // The frame into target_ (cleared first; the scissor, if set, limits both).
  void draw_frame(const glm::mat4& view_projection, vec3 eye, const RenderSettings& settings);
  // Depth of every mesh into the bound target, colour untouched; stencil 1 where covered. With
  // `occlusion` only the clusters camera_culler_ finds visible, their meshes flagged in
  // camera_drawn_. Then sets the state that keeps, per pixel, the first fragment at that depth.
  void draw_depth(const glm::mat4& view_projection, vec3 eye, bool occlusion,
                  const DetailView& detail);
  void refine_band(const ViewCamera& camera, const RenderSettings& settings);
  // The sky where the depth buffer is still clear, for the bound target and this view.
  void draw_sky(const glm::mat4& view_projection, const RenderSettings& settings);
  void render_planar_reflections(const ViewCamera& camera, int width, int height,
                                 const RenderSettings& settings);

  // The scene mirrored about the plane of one or more coplanar mirrors or glossy plates.
  struct PlanarReflection {
    std::vector<int> meshes;
    glm::vec4 plane{0.0f};  // GpuMesh::plane of the first
    Bounds bounds;          // of the meshes
    bool visible = false;   // drawn this frame (in front of the plane, within the cap)
    int width = 0, height = 0;
    gl::Framebuffer framebuffer;
    gl::Texture colour, depth;
  };
  std::vector<PlanarReflection> planar_;
  // Per material: a glossy lobe's directional albedo at kGlossyAlbedoEntries view cosines
  // (lb::glossy_albedo), the factor that its blurred reflection takes (empty for others).
  std::vector<std::vector<float>> glossy_albedo_;

  std::string shader_directory_;
  // Scene shader variants by their defines (shaders/scene.frag explains why).
  const ShaderProgram& scene_program(const std::vector<std::string>& defines);
  std::map<std::string, ShaderProgram> scene_programs_;
  ShaderProgram shadow_program_, tonemap_program_, flat_program_, accumulate_program_;
  ShaderProgram depth_program_;    // scene.vert + depth.frag, the depth pre-pass
  // The ALPHA_CUT variants of the shadow and depth passes (viewer/alpha_cut.h), built with the
  // first scene that has cut meshes (set_scene or update_scene: build_alpha_programs).
  ShaderProgram shadow_alpha_program_, depth_alpha_program_;
  void build_alpha_programs();
  DepthPrograms shadow_programs() const;
  DepthPrograms depth_programs() const;
  ShaderProgram sky_programs_[2];  // without, with an equirect texture
  std::unique_ptr<GpuScene> scene_;
  std::unique_ptr<OcclusionCuller> camera_culler_;  // every mesh of scene_, for the camera
  std::vector<char> camera_drawn_;                  // per mesh: drawn by the last pre-pass
  OcclusionSchedule camera_schedule_;               // whether a camera pass queries
  // Whether this camera pass queries: Culling and camera_schedule_ (a pass that does not
  // counts as done here; draw_depth reports one that does).
  bool camera_queries();
  ShadowMaps shadows_;
  LampShadowMaps lamp_shadows_;
  LightTable light_table_;
  // Renders the shadow cubes (and, with lists on, the light lists) from `shadows`.
  void build_shadow_cubes(const ShadowSettings& shadows, bool fresh);
  // `shadows` with the size set_scene chose when its resolution is 0 (automatic).
  ShadowSettings with_resolution(ShadowSettings shadows) const;
  LightLists light_lists_;        // as built, or every light
  LightLists all_lights_;         // every light in every chunk: lists off
  int scene_generation_ = 0;      // counts set_scene and update_scene calls
  EnvironmentCubes environment_;  // the curved specular objects' captures
  gl::Framebuffer target_;
  gl::Texture target_colour_, target_depth_;
  gl::VertexArray empty_vertex_array_;
  // What a still view must keep equal for its frames to accumulate.
  struct AccumulationKey {
    glm::mat4 view_projection{0.0f};
    vec3 eye{0.0f};
    Term term = Term::all;
    bool direct = false, shadows = false, caustics = false, radiosity = false, ambient = false;
    vec3 ambient_radiance{0.0f};
    DirectMode direct_mode = DirectMode::full;
    int refine_bands = 0;
    bool planar_reflections = true;
    bool bump_full_resolution = false;
    float detail_pixels = 0.0f;
    int scene_generation = -1;
    bool operator==(const AccumulationKey&) const = default;
  };
  AccumulationKey accumulation_key_;
  vec2 pixel_offset_{0.0f};  // render()'s, for its planar passes too
  gl::Framebuffer accumulation_;
  gl::Texture accumulation_colour_;
  int accumulated_ = 0;
  bool shows_accumulation_ = false;
  int width_ = 0, height_ = 0;
  Culling culling_;
  FrameStats stats_;
};

}  // namespace lb
