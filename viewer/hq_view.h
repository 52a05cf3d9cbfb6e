#pragma once
// HQ mode in the window: HqRenderer passes (bake/hq/hq_render.h) on a worker thread into a
// film the size of the window, and the newest finished pass's average shown through the raster
// view's own tone mapping shader (tonemap.frag). The GUI thread never waits on a pass: a camera
// move, a resize or new settings only raise the cancel flag, which the pass reads after each
// wave of a tile (milliseconds), and the next pass starts once that job has ended and the
// camera stands still. A cancelled pass leaves nothing behind; results of a superseded view
// are dropped. The film then holds exactly what `lightbake render` accumulates for the same
// camera, size, seed, samples per pass and passes, so it has the same bits.

#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "bake/bake_result.h"
#include "bake/hq/hq_render.h"
#include "bake/io/image_io.h"
#include "viewer/background_job.h"
#include "viewer/gl_resources.h"
#include "viewer/shader_program.h"
#include "viewer/view_camera.h"

namespace lb {

class HqView {
 public:
  // Builds the tone mapping program: needs the window's GL context current.
  explicit HqView(const std::string& shader_directory);
  ~HqView();
  HqView(const HqView&) = delete;
  HqView& operator=(const HqView&) = delete;

  // The bake HQ mode traces over (copied; null: none, HQ mode then shows nothing). Cancels the
  // running pass.
  void set_bake(const Scene& scene, const BakeResult* bake);
  bool has_bake() const { return bool(source_); }

  // The renderer's settings (width and height are the window's, set by update()); max_passes
  // stops refining after that many passes (0: never).
  void set_params(const HqParams& params, int max_passes);
  const HqParams& params() const { return params_; }
  int max_passes() const { return max_passes_; }

  // Every frame while HQ mode is on: the view to refine and the film size. A change cancels
  // the running pass and forgets the shown film; a new job starts once the previous one has
  // ended and `still` (the camera did not move this frame).
  void update(const Camera& camera, int width, int height, bool still);
  // HQ mode off: cancels the running pass (without waiting) and forgets the film.
  void pause();

  // Whether a finished pass of the current view is there to show.
  bool ready() const;
  // Uploads the newest film average if it changed and draws it tone mapped into the bound
  // framebuffer (the window's) at width x height, the film's size.
  void present(const ToneMap& tone, int width, int height);
  // What the last present() drew: passes, samples per pixel, and its radiance (W/(sr m^2),
  // row 0 at the top, width x height).
  int shown_passes() const { return shown_passes_; }
  uint64_t shown_samples_per_pixel() const { return shown_spp_; }
  const std::vector<vec3>& shown_pixels() const { return shown_; }
  int shown_width() const { return shown_width_; }
  int shown_height() const { return shown_height_; }
  // The running job: its stage text and the fraction of its current pass done, and its
  // failure (empty if none).
  bool running() const { return job_.running(); }
  std::string stage() const { return job_.stage(); }
  double fraction() const { return job_.fraction(); }
  std::string error() const { return job_.error(); }
  double last_pass_seconds() const;

 private:
  struct Source;    // the scene and bake copied at set_bake
  struct Prepared;  // the BakedScene and renderer built from them on the worker
  // Everything a job depends on: a change restarts it.
  struct Key {
    const Source* source = nullptr;
    Camera camera;
    int width = 0, height = 0;
    HqParams params;
    int max_passes = 0;
    bool operator==(const Key& other) const;
  };
  void invalidate();  // cancel the job and drop its results
  void start(const Key& key);
  std::shared_ptr<const Prepared> prepare(const std::shared_ptr<const Source>& source,
                                          const HqParams& params);

  ShaderProgram tonemap_program_;
  gl::Texture texture_;
  gl::VertexArray empty_vertex_array_;

  std::shared_ptr<const Source> source_;
  HqParams params_;
  int max_passes_ = 0;
  Key wanted_, running_key_;
  bool have_wanted_ = false, started_ = false;

  mutable std::mutex mutex_;  // guards the fields below, written by the worker
  std::shared_ptr<const Prepared> prepared_;
  uint64_t generation_ = 0;  // bumped by invalidate(): a worker of an older one publishes nothing
  std::vector<vec3> latest_;
  int latest_passes_ = 0;
  uint64_t latest_spp_ = 0;
  double last_pass_seconds_ = 0.0;
  bool fresh_ = false;  // latest_ not uploaded yet

  std::vector<vec3> shown_;
  int shown_passes_ = 0, shown_width_ = 0, shown_height_ = 0;
  uint64_t shown_spp_ = 0;

  BackgroundJob job_;  // last: joined before the fields above are destroyed
};

// The lb::Camera HQ mode renders the view from: the scene camera the view still equals (its
// lens and all, as `render --camera` takes it), else a pinhole at the view.
Camera hq_camera(const ViewCamera& view, const Scene& scene, const Camera& start);

}  // namespace lb
