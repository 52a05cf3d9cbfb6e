#include "viewer/hq_view.h"

#include <algorithm>
#include <utility>

namespace lb {

struct HqView::Source {
  Scene scene;
  BakeResult bake;
};

// BakedScene points into the BakeResult, so it lives beside the Source that holds it.
struct HqView::Prepared {
  std::shared_ptr<const Source> source;
  HqParams params;
  BakedScene baked;
  std::unique_ptr<HqRenderer> renderer;
};

namespace {

bool same_camera(const Camera& a, const Camera& b) {
  return a.name == b.name && a.position == b.position && a.target == b.target && a.up == b.up &&
         a.vertical_fov_deg == b.vertical_fov_deg && a.aperture_radius == b.aperture_radius &&
         a.focus_distance == b.focus_distance;
}

// The settings that change the image (the shard fields stay at one shard).
bool same_params(const HqParams& a, const HqParams& b) {
  return a.width == b.width && a.height == b.height && a.samples_per_side == b.samples_per_side &&
         a.max_depth == b.max_depth && a.throughput_cutoff == b.throughput_cutoff &&
         a.reuse_light_choice == b.reuse_light_choice && a.tile_size == b.tile_size &&
         a.max_wave_paths == b.max_wave_paths && a.seed == b.seed && a.direct == b.direct &&
         a.illumination_map == b.illumination_map && a.radiosity == b.radiosity &&
         a.final_gather == b.final_gather && a.directional == b.directional;
}

bool same_view(const ViewCamera& view, const Camera& camera) {
  const ViewCamera other = ViewCamera::from(camera);
  return view.position == other.position && view.target == other.target && view.up == other.up &&
         view.vertical_fov_deg == other.vertical_fov_deg;
}

}  // namespace

bool HqView::Key::operator==(const Key& other) const {
  return source == other.source && same_camera(camera, other.camera) && width == other.width &&
         height == other.height && same_params(params, other.params) &&
         max_passes == other.max_passes;
}

Camera hq_camera(const ViewCamera& view, const Scene& scene, const Camera& start) {
  if (same_view(view, start)) return start;
  for (const Camera& camera : scene.cameras)
    if (same_view(view, camera)) return camera;
  Camera camera;  // moved away from every scene camera: a pinhole at the view
  camera.name = "view";
  camera.position = view.position;
  camera.target = view.target;
  camera.up = view.up;
  camera.vertical_fov_deg = view.vertical_fov_deg;
  return camera;
}

HqView::HqView(const std::string& shader_directory)
    : tonemap_program_(ShaderProgram::build(shader_directory, "fullscreen.vert", "tonemap.frag")),
      texture_(gl::make_texture()),
      empty_vertex_array_(gl::make_vertex_array()) {
  tonemap_program_.use();
  tonemap_program_.set("u_radiance", 0);
  glUseProgram(0);
  glBindTexture(GL_TEXTURE_2D, texture_.get());
  // Nearest: one texel per window pixel, the film's value unfiltered.
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glBindTexture(GL_TEXTURE_2D, 0);
  gl::check_errors("HQ view texture");
}

HqView::~HqView() {
  job_.stop();
}

void HqView::set_bake(const Scene& scene, const BakeResult* bake) {
  invalidate();
  if (!bake) {
    source_.reset();
    return;
  }
  auto source = std::make_shared<Source>();
  source->scene = scene;
  source->bake = *bake;
  source_ = std::move(source);
}

void HqView::set_params(const HqParams& params, int max_passes) {
  params_ = params;
  max_passes_ = std::max(max_passes, 0);
}

void HqView::invalidate() {
  job_.cancel();
  std::lock_guard lock(mutex_);
  ++generation_;
  latest_.clear();
  latest_passes_ = 0;
  latest_spp_ = 0;
  fresh_ = false;
  shown_.clear();
  shown_passes_ = 0;
  shown_spp_ = 0;
  started_ = false;
}

void HqView::pause() {
  if (have_wanted_) invalidate();
  have_wanted_ = false;
}

void HqView::update(const Camera& camera, int width, int height, bool still) {
  if (!source_ || width <= 0 || height <= 0) return;
  Key key;
  key.source = source_.get();
  key.camera = camera;
  key.width = width;
  key.height = height;
  key.params = params_;
  key.params.width = width;
  key.params.height = height;
  key.max_passes = max_passes_;
  if (!have_wanted_ || !(key == wanted_)) {
    invalidate();
    wanted_ = key;
    have_wanted_ = true;
  }
  // The previous job may still be ending its wave: start next frame rather than wait here.
  if (!started_ && still && !job_.running()) start(key);
}

void HqView::start(const Key& key) {
  started_ = true;
  running_key_ = key;
  uint64_t generation = 0;
  {
    std::lock_guard lock(mutex_);
    generation = generation_;
  }
  std::shared_ptr<const Source> source = source_;
  job_.start([this, source, key, generation](const Progress& progress) {
    progress.update("preparing the scene", 0.0);
    const std::shared_ptr<const Prepared> prepared = prepare(source, key.params);
    Film film(key.params.width, key.params.height);
    HqStats stats;
    for (int pass = 0; key.max_passes == 0 || pass < key.max_passes; ++pass) {
      prepared->renderer->render_pass(key.camera, film, stats, progress);
      std::vector<vec3> average = film.average();
      std::lock_guard lock(mutex_);
      if (generation != generation_) return;  // superseded while the pass finished
      latest_ = std::move(average);
      latest_passes_ = film.passes;
      latest_spp_ = film.samples_per_pixel;
      last_pass_seconds_ = stats.pass_seconds.back();
      fresh_ = true;
    }
    progress.update("done", 1.0);
  });
}

// The renderer (with its own accelerator, a BVH build) is kept while the bake and the
// settings, film size included, stay the same: a camera move costs no rebuild, a resize does.
std::shared_ptr<const HqView::Prepared> HqView::prepare(const std::shared_ptr<const Source>& source,
                                                        const HqParams& params) {
  {
    std::lock_guard lock(mutex_);
    if (prepared_ && prepared_->source == source && same_params(prepared_->params, params))
      return prepared_;
  }
  auto prepared = std::make_shared<Prepared>();
  prepared->source = source;
  prepared->params = params;
  // As `lightbake render`: an export made with `--contents all` holds the direct light in its
  // map already.
  if (source->bake.illumination.holds_direct_light) prepared->params.direct = false;
  prepared->baked = make_baked_scene(source->scene, source->bake);
  prepared->baked.directional = prepared->baked.directional && params.directional;
  prepared->renderer = std::make_unique<HqRenderer>(prepared->baked, prepared->params);
  prepared->params = params;  // the key it is found by
  std::lock_guard lock(mutex_);
  prepared_ = prepared;
  return prepared;
}

bool HqView::ready() const {
  std::lock_guard lock(mutex_);
  return latest_passes_ > 0;
}

double HqView::last_pass_seconds() const {
  std::lock_guard lock(mutex_);
  return last_pass_seconds_;
}

void HqView::present(const ToneMap& tone, int width, int height) {
  {
    std::lock_guard lock(mutex_);
    if (fresh_) {
      shown_ = latest_;
      shown_passes_ = latest_passes_;
      shown_spp_ = latest_spp_;
      shown_width_ = running_key_.width;
      shown_height_ = running_key_.height;
      fresh_ = false;
      // GL rows go bottom up; the film's row 0 is the top.
      std::vector<vec3> rows(shown_.size());
      const size_t w = size_t(shown_width_);
      for (int y = 0; y < shown_height_; ++y)
        std::copy_n(shown_.begin() + std::ptrdiff_t(size_t(y) * w), w,
                    rows.begin() + std::ptrdiff_t(size_t(shown_height_ - 1 - y) * w));
      glBindTexture(GL_TEXTURE_2D, texture_.get());
      glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
      glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB32F, shown_width_, shown_height_, 0, GL_RGB, GL_FLOAT,
                   rows.data());
    }
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glViewport(0, 0, width, height);
  glDisable(GL_DEPTH_TEST);
  tonemap_program_.use();
  tonemap_program_.set("u_exposure", tone.exposure);
  tonemap_program_.set("u_curve", int(tone.curve));
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, texture_.get());
  glBindVertexArray(empty_vertex_array_.get());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glBindTexture(GL_TEXTURE_2D, 0);
  glUseProgram(0);
  glEnable(GL_DEPTH_TEST);
}

}  // namespace lb
