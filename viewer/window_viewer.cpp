#include "viewer/window_viewer.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <future>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "viewer/renderer.h"  // glad first: GLFW and ImGui's backend must not include GL

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include "bake/camera.h"
#include "bake/export/gltf_bake_read.h"
#include "bake/export/gltf_export.h"
#include "bake/io/image_io.h"
#include "bake/io/scene_load.h"
#include "bake/message_line.h"
#include "bake/pipeline/bake_io.h"
#include "viewer/bake_job.h"
#include "viewer/bake_settings_panel.h"
#include "viewer/export_job.h"
#include "viewer/file_watch.h"
#include "viewer/hq_view.h"
#include "viewer/light_group_mix.h"
#include "viewer/snapshot.h"
#include "viewer/window_input.h"

namespace lb {

namespace {

struct LoadedScene {
  // On the heap, so the accel's reference to it survives the move into the app.
  std::unique_ptr<Scene> scene;
  std::unique_ptr<Accel> accel;  // for the camera's limits and fit (viewer/view_camera.h)
  std::optional<BakeResult> bake;
  std::vector<std::string> warnings;
};

// Runs on a worker thread: parse, validate, build the accel, and read the bake directory if
// there is one (or the baked light inside a glTF that `lightbake export` wrote).
LoadedScene load_everything(const std::string& path, const std::string& bake_dir,
                            const SceneLoadOptions& options) {
  LoadedScene loaded;
  LoadResult result = load_scene(path, options);
  loaded.scene = std::make_unique<Scene>(std::move(result.scene));
  loaded.warnings = std::move(result.warnings);
  loaded.accel = std::make_unique<Accel>(*loaded.scene);
  if (!bake_dir.empty()) {
    loaded.bake = load_bake(bake_dir, *loaded.scene);
  } else if (is_lightbake_gltf(path)) {
    loaded.bake = read_gltf_bake(path, *loaded.scene);  // `lightbake export`'s light
  }
  return loaded;
}

class ViewerApp {
 public:
  ViewerApp(GLFWwindow* window, WindowInput& input, const ViewerOptions& options)
      : window_(window),
        input_(input),
        options_(options),
        settings_(options.settings),
        renderer_(options.shader_directory),
        hq_(options.shader_directory),
        hq_on_(options.hq),
        panel_shown_(!options.hide_panel) {
    start_loading(options.scene_path, Load::first);
    set_export_path(default_export_path(options.scene_path));
    std::snprintf(open_path_, sizeof open_path_, "%s", options.scene_path.c_str());
  }

  int run() {
    auto last = std::chrono::steady_clock::now();
    while (!glfwWindowShouldClose(window_)) {
      // While HQ passes run for a still view, at most ~30 frames a second (any event wakes the
      // loop at once), so the GUI thread leaves the cores to the pass.
      if (hq_on_ && hq_.running() && !camera_moved_)
        glfwWaitEventsTimeout(1.0 / 30.0);
      else
        glfwPollEvents();
      if (!poll_loading()) return 1;
      poll_file_change();
      poll_bake();
      poll_export();
      const auto now = std::chrono::steady_clock::now();
      const float dt = std::chrono::duration<float>(now - last).count();
      last = now;
      frame_ms_ = 0.9f * frame_ms_ + 0.1f * dt * 1000.0f;
      handle_input(dt);

      int width = 0, height = 0;
      glfwGetFramebufferSize(window_, &width, &height);
      if (width > 0 && height > 0) {
        if (scene_ && update_hq(width, height)) {
          hq_.present(settings_.tone, width, height);
        } else if (scene_) {
          // While the camera moves, draw fewer pixels (1/4, 1/9 or 1/16, adapted to the frame
          // time) and scale them up, so the window keeps up on a software rasteriser; full
          // resolution once it rests.
          const bool moving = camera_moved_ && options_.frames == 0 && !full_resolution_only_;
          if (moving && frame_ms_ > 80.0f) moving_divisor_ = std::min(moving_divisor_ + 1, 4);
          if (moving && frame_ms_ < 25.0f) moving_divisor_ = std::max(moving_divisor_ - 1, 2);
          const int divisor = moving ? moving_divisor_ : 1;
          // While the first HQ pass of a still view runs, the raster frame is redrawn only
          // 4 times a second (panel edits still show), leaving the cores to the pass.
          const auto now = std::chrono::steady_clock::now();
          const bool hq_waiting = hq_on_ && hq_.running() && !camera_moved_;
          const bool same_frame = divisor == 1 && raster_divisor_ == 1 && raster_width_ == width &&
                                  raster_height_ == height;
          if (!hq_waiting || !same_frame || now >= next_raster_) {
            // Moving, planar mirrors read the environment capture: from above a level their
            // passes were most of the frame (docs/viewer.md, the moving camera); and meshes
            // far away are drawn coarser, up to one pixel of the smaller frame off
            // (viewer/mesh_detail.h).
            RenderSettings frame_settings = settings_;
            frame_settings.planar_reflections = divisor == 1;
            if (divisor > 1) frame_settings.detail_pixels = std::max(settings_.detail_pixels, 1.0f);
            renderer_.render(camera_, std::max(1, width / divisor), std::max(1, height / divisor),
                             frame_settings);
            next_raster_ = now + std::chrono::milliseconds(250);
            raster_divisor_ = divisor;
            raster_width_ = width;
            raster_height_ = height;
          }
          renderer_.present(0, settings_.tone, width, height);
        } else {
          glBindFramebuffer(GL_FRAMEBUFFER, 0);
          glViewport(0, 0, width, height);
          glClearColor(0.1f, 0.1f, 0.12f, 1.0f);
          glClear(GL_COLOR_BUFFER_BIT);
        }
      }
      ImGui_ImplOpenGL3_NewFrame();
      ImGui_ImplGlfw_NewFrame();
      ImGui::NewFrame();
      if (panel_shown_) panel();
      ImGui::Render();
      if (ImGui::GetIO().WantTextInput != text_input_) {  // for --log-actions' readers
        text_input_ = ImGui::GetIO().WantTextInput;
        log_line(text_input_ ? "text input on" : "text input off");
      }
      ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
      input_.end_frame();
      if (width > 0 && height > 0 && !automation(width, height)) return exit_status_;
      glfwSwapBuffers(window_);
    }
    return exit_status_;
  }

 private:
  // ---- background work ------------------------------------------------------------------
  // The first load (the command line's scene and bake directory), a reload of the shown file
  // (the camera and view settings stay) or another file opened (the camera starts afresh).
  // A reload or an opened file bakes afresh (unless --no-bake): a bake directory belongs to
  // the file as it was at start.
  enum class Load { first, reload, open };

  void start_loading(const std::string& path, Load kind) {
    if (loading_.valid()) {  // one load at a time: the newest request waits for it
      pending_load_ = {path, kind};
      return;
    }
    const std::string bake_dir = kind == Load::first ? options_.bake_dir : std::string();
    const SceneLoadOptions load = options_.load;
    // Watched from before the read, so a save during the load is seen as a change.
    watch_.watch(path);
    loading_ = std::async(std::launch::async,
                          [path, bake_dir, load] { return load_everything(path, bake_dir, load); });
    loading_kind_ = kind;
    loading_path_ = path;
  }

  bool poll_loading() {
    if (!loading_.valid() ||
        loading_.wait_for(std::chrono::seconds(0)) != std::future_status::ready)
      return true;
    try {
      LoadedScene loaded = loading_.get();
      for (const auto& warning : loaded.warnings)
        print_message("warning", warning);
      show_scene(std::move(loaded));
    } catch (const std::exception& e) {
      print_message("error", e.what());
      // Automation has nothing to show: fail instead of waiting.
      if (options_.frames > 0 && !scene_) return false;
      error_ = e.what();
      // A file that is not there: back to watching the shown one. (One that failed to parse
      // stays watched: its next save loads it.)
      if (scene_ && !std::filesystem::exists(loading_path_)) watch_.watch(scene_path_);
    }
    if (pending_load_) {
      const auto [path, kind] = *pending_load_;
      pending_load_.reset();
      start_loading(path, kind);
    }
    return true;
  }

  // The loaded scene replaces the shown one (which stays when a load fails).
  void show_scene(LoadedScene loaded) {
    const bool keep_view = loading_kind_ == Load::reload && scene_;
    // First, as it may throw (--camera names none): the shown scene then stays as it was.
    const std::string camera_name = loading_kind_ == Load::first ? options_.camera : "";
    const Camera start_camera = select_camera(*loaded.scene, camera_name);
    // The old bake is of the old scene: no partial or result of it may reach the new one.
    if (baking_) bake_job_.cancel();
    baking_ = false;
    showing_partial_ = false;
    partial_stats_.reset();
    accel_.reset();  // it refers to the scene it was built over
    const size_t old_cameras = scene_ ? scene_->cameras.size() : 0;
    scene_ = std::move(loaded.scene);
    accel_ = std::move(loaded.accel);
    bake_ = std::move(loaded.bake);
    reset_groups();
    upload(true);
    start_camera_ = start_camera;
    // The scene's cameras first, then the views saved by hand (kept across loads).
    std::vector<ViewCamera> views;
    for (const Camera& camera : scene_->cameras) views.push_back(ViewCamera::from(camera));
    views.insert(views.end(), saved_views_.begin() + ptrdiff_t(old_cameras), saved_views_.end());
    saved_views_ = std::move(views);
    if (!keep_view) {
      camera_ = ViewCamera::from(start_camera_);
      if (options_.exposure_from_camera || loading_kind_ != Load::first)
        settings_.tone.exposure = start_camera_.exposure;
    }
    if (loading_kind_ == Load::open) set_export_path(default_export_path(loading_path_));
    scene_path_ = loading_path_;
    status_ = scene_path_;
    error_.clear();
    // A reload keeps the panel's settings; a file opened starts from the command line's and
    // its own (bake/pipeline/bake_settings.h).
    if (!keep_view) {
      options_.bake = resolve_bake_params(*scene_, options_.bake_settings);
      quality_ = options_.bake.quality;
    }
    std::printf("%s %s: %zu triangles\n",
                loading_kind_ == Load::first    ? "loaded"
                : loading_kind_ == Load::reload ? "reloaded"
                                                : "opened",
                scene_path_.c_str(), triangle_count(*scene_));
    std::fflush(stdout);  // tests and scripts wait for this line
    if (!bake_ && options_.bake_on_load) start_bake();
  }

  // Twice a second: the shown scene's file changed on disk (saved from an editor) -> reload.
  void poll_file_change() {
    const auto now = std::chrono::steady_clock::now();
    if (now < next_file_check_) return;
    next_file_check_ = now + std::chrono::milliseconds(500);
    if (loading_.valid() || !watch_.changed()) return;
    const std::string path = watch_.path();  // the shown file, or one that failed to parse
    start_loading(path, scene_ && path == scene_path_ ? Load::reload : Load::open);
  }

  void open_scene(const std::string& path) {
    if (path.empty()) return;
    std::snprintf(open_path_, sizeof open_path_, "%s", path.c_str());
    start_loading(path, path == scene_path_ && scene_ ? Load::reload : Load::open);
  }

  void start_bake() {
    if (!scene_) return;
    bake_job_.start(*scene_, options_.bake);
    baking_ = true;
    partials_shown_ = 0;
  }

  // Shows the newest partial result while the bake refines (the renderer copies what it
  // needs, a re-upload of vertex colours and the atlas), then the final one.
  void poll_bake() {
    if (!baking_) return;
    const bool running = bake_job_.running();  // read first: a partial taken after is not stale
    const auto now = std::chrono::steady_clock::now();
    // update_scene also redraws the environment capture (about 50 ms on llvmpipe for the
    // room's glass ball) and the first one compiles shader variants: leave at least 8 times
    // the last upload's time (at most 1 s) between uploads, so the window stays interactive.
    if (running && now >= next_upload_) {
      if (auto partial = bake_job_.take_partial()) {
        renderer_.update_scene(*scene_, &*partial);
        const auto end = std::chrono::steady_clock::now();
        upload_ms_ = std::chrono::duration<float>(end - now).count() * 1000.0f;
        next_upload_ = end + std::min<std::chrono::steady_clock::duration>(8 * (end - now),
                                                                           std::chrono::seconds(1));
        partial_stats_ = partial->radiosity.stats;
        showing_partial_ = true;
        ++partials_shown_;
      }
    }
    if (running) return;
    baking_ = false;
    bake_job_.take_partial();  // a stale one, if any
    partial_stats_.reset();
    if (auto result = bake_job_.take_result()) {
      bake_ = std::move(result);
      reset_groups();
      upload(false);
      if (options_.frames > 0)  // automation: say how the bake refined on screen
        std::printf("baked: %d partial results shown, last upload %.1f ms\n", partials_shown_,
                    double(upload_ms_));
    } else {
      // Cancelled or failed: back to the last complete bake (or none).
      if (showing_partial_) renderer_.update_scene(*scene_, bake_ ? &*bake_ : nullptr);
      if (!bake_job_.error().empty()) {
        error_ = "bake failed: " + bake_job_.error();
        print_message("error", error_);
      }
    }
    showing_partial_ = false;
  }

  // The progress bar's text: the stage, and once radiosity partials arrive, how far the
  // shown solution is from converged (unsent power as a fraction of the emitted).
  std::string bake_progress_text() const {
    std::string text = bake_job_.stage();
    if (partial_stats_ && partial_stats_->shots > 0) {
      char buffer[96];
      std::snprintf(buffer, sizeof buffer, " - %llu shots, residual %.2f%%",
                    static_cast<unsigned long long>(partial_stats_->shots),
                    partial_stats_->residual_fraction * 100.0);
      text += buffer;
    }
    return text;
  }

  // --frames/--screenshot: returns false when the app should stop.
  bool automation(int width, int height) {
    if (options_.frames <= 0 || !scene_ || baking_) return true;
    if (!options_.export_path.empty() && !export_requested_) {  // as if the button was pressed
      export_requested_ = true;
      set_export_path(options_.export_path);
      start_export();
    }
    if (exporting_) return true;
    if (options_.hq && !hq_automation_done_) {
      if (!bake_) {
        std::fprintf(stderr, "lightbake: error: HQ mode needs a bake\n");
        exit_status_ = 1;
        return false;
      }
      if (!hq_.error().empty()) {
        print_message("error", "HQ mode: " + hq_.error());
        exit_status_ = 1;
        return false;
      }
      ++hq_frames_;
      // The frame just drawn shows the film once it has all its passes (the job stops there).
      if (!hq_on_ || hq_.shown_passes() < std::max(options_.hq_passes, 1)) return true;
      if (!options_.hq_exr.empty()) {
        Image film(hq_.shown_width(), hq_.shown_height(), 3);
        for (size_t i = 0; i < hq_.shown_pixels().size(); ++i)
          for (int c = 0; c < 3; ++c) film.pixels[i * 3 + size_t(c)] = hq_.shown_pixels()[i][c];
        write_exr(options_.hq_exr, film, ExrPixelType::float32);
      }
      std::printf(
          "hq: %d passes, %llu samples per pixel, %dx%d, last pass %.2f s, %d frames "
          "drawn meanwhile (%.1f ms/frame)\n",
          hq_.shown_passes(), static_cast<unsigned long long>(hq_.shown_samples_per_pixel()),
          hq_.shown_width(), hq_.shown_height(), hq_.last_pass_seconds(), hq_frames_,
          double(frame_ms_));
      take_screenshot(width, height);
      hq_automation_done_ = true;
      hq_on_ = false;  // back to raster for the frames below
      return true;
    }
    if (++frames_shown_ < options_.frames) return true;
    // The stochastic direct light's still frames refine to the full evaluation: the raster
    // screenshot waits for it, so it is the image `snapshot` makes.
    if (!options_.hq && !renderer_.exact(settings_)) return true;
    if (!options_.hq) take_screenshot(width, height);
    if (panel_shown_)
      std::printf("panel: %.0fx%.0f px at %.0f,%.0f in %dx%d\n", double(panel_size_.x),
                  double(panel_size_.y), double(panel_pos_.x), double(panel_pos_.y), width, height);
    if (options_.hq) std::printf("raster: %d frames after HQ\n", frames_shown_);
    exit_status_ = error_.empty() && export_error_.empty() ? 0 : 1;
    return false;
  }

  void take_screenshot(int width, int height) {
    if (options_.screenshot.empty()) return;
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    glReadBuffer(GL_BACK);
    write_png8(options_.screenshot, width, height, 3, Renderer::read_display(width, height));
    std::printf("wrote %s (%dx%d)\n", options_.screenshot.c_str(), width, height);
  }

  // ---- HQ mode ----------------------------------------------------------------------------
  // Steers the HQ job for this frame; true when its film is to be drawn instead of raster.
  bool update_hq(int width, int height) {
    if (!hq_on_ || !hq_.has_bake()) {
      hq_.pause();
      return false;
    }
    hq_.set_params(options_.hq_params, options_.hq_passes);
    // At rest: unmoved for a tenth of a second, so the pauses between a drag's mouse events
    // do not start (and at once cancel) a pass each.
    const bool still =
        std::chrono::steady_clock::now() - last_move_ > std::chrono::milliseconds(100);
    hq_.update(hq_camera(camera_, *scene_, start_camera_), width, height, still);
    return hq_.ready();
  }

  void hq_panel() {
    if (!ImGui::CollapsingHeader("HQ ray tracing")) return;
    ImGui::Checkbox("HQ (H)", &hq_on_);
    ImGui::SameLine();
    ImGui::TextDisabled("refines at rest");
    if (!bake_) {
      ImGui::TextColored(ImVec4(1, 0.8f, 0.3f, 1), "HQ needs a bake: %s",
                         baking_ ? "showing raster until it ends" : "showing raster");
    } else if (hq_on_) {
      if (hq_.ready())
        ImGui::Text("%llu spp, %d passes, %.2f s/pass",
                    static_cast<unsigned long long>(hq_.shown_samples_per_pixel()),
                    hq_.shown_passes(), hq_.last_pass_seconds());
      else
        ImGui::Text("raster until the first pass");
      if (hq_.running())
        ImGui::ProgressBar(float(hq_.fraction()), ImVec2(-1, 0), hq_.stage().c_str());
      if (!hq_.error().empty()) {
        ImGui::PushTextWrapPos(0.0f);
        ImGui::TextColored(ImVec4(1, 0.4f, 0.4f, 1), "%s", hq_.error().c_str());
        ImGui::PopTextWrapPos();
      }
    }
    HqParams& params = options_.hq_params;
    const ImGuiSliderFlags clamp = ImGuiSliderFlags_AlwaysClamp;
    // A change restarts the film (the new settings are part of what the job depends on).
    // The slider's text: the side and the samples per pixel per pass it makes.
    const std::string side_format =
        "%d (" + std::to_string(params.samples_per_side * params.samples_per_side) + " spp)";
    ImGui::SliderInt("spp side", &params.samples_per_side, 1, 8, side_format.c_str(), clamp);
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("samples per pixel per pass: side x side");
    ImGui::DragInt("passes", &options_.hq_passes, 1, 0, 1 << 20, "%d", clamp);
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("refining stops after this many (0: never)");
  }

  // ---- export (the panel's Export button) -------------------------------------------------
  void set_export_path(const std::string& path) {
    std::snprintf(export_path_, sizeof export_path_, "%s", path.c_str());
  }

  // The shown bake (or, without one, a bake made first with the panel's params) to the path
  // in the text field, with the panel's export settings; a refusal or failure becomes the
  // panel's error line. With directional maps when asked, or when the view draws a bake's
  // bands (the view's setting on, and the shown bake, or the one the job makes, a directional
  // one); a shown glTF's band is the file's, not a bake's.
  void start_export() {
    if (!scene_ || baking_ || exporting_) return;
    export_error_.clear();
    export_done_.clear();
    const IlluminationMaps* maps = bake_ ? &bake_->illumination : nullptr;
    const bool bands = maps ? !maps->radiance.empty() &&
                                  maps->l1_share.size() == maps->radiance.size()
                            : options_.bake.illumination.directional;
    ExportSettings settings = export_settings_;
    settings.directional = (settings.directional || (settings_.directional && bands)) &&
                           !is_lightbake_gltf(scene_path_);
    if (export_job_.start(export_path_, *scene_, bake_ ? &*bake_ : nullptr, options_.bake,
                          settings)) {
      exporting_ = true;
    } else {
      export_error_ = export_job_.error();
      print_message("error", export_error_);
    }
  }

  void poll_export() {
    if (!exporting_ || export_job_.running()) return;
    exporting_ = false;
    if (auto info = export_job_.take_result()) {
      char buffer[160];
      std::snprintf(buffer, sizeof buffer, "wrote %zu meshes, %zu bytes", info->meshes,
                    info->bytes);
      export_done_ = buffer;
      std::printf("exported %s (%zu bytes%s)\n", export_path_, info->bytes,
                  info->directional ? ", directional" : "");
    } else if (!export_job_.error().empty()) {
      export_error_ = export_job_.error();
      print_message("error", export_error_);
    } else {
      export_done_ = export_job_.stage();  // cancelled
    }
  }

  // ---- input ------------------------------------------------------------------------------
  void handle_input(float dt) {
    const ViewCamera before = camera_;
    for (const InputEvent& event : input_.take()) handle_event(event);
    handle_fly_keys(dt);
    camera_moved_ = before.position != camera_.position || before.target != camera_.target ||
                    before.vertical_fov_deg != camera_.vertical_fov_deg;
    if (camera_moved_) last_move_ = std::chrono::steady_clock::now();
  }

  // One queued event, in the order they came. ImGui's WantCapture flags are those of the last
  // frame, the state the user saw when acting: a drag that starts on the panel, a key typed
  // into one of its text fields, a scroll over it are ImGui's alone.
  void handle_event(const InputEvent& event) {
    const ImGuiIO& io = ImGui::GetIO();
    switch (event.kind) {
      case InputEvent::Kind::key:
        if (event.action == GLFW_RELEASE) {
          held_keys_.erase(event.code);
        } else if (event.action == GLFW_PRESS && !io.WantCaptureKeyboard) {
          held_keys_.insert(event.code);
          key_tap(event.code, event.mods);
        } else if (event.action == GLFW_PRESS) {
          log_action(event.code, "to the panel");
        }
        break;
      case InputEvent::Kind::button:
        if (event.code < 0 || event.code >= int(dragging_.size())) break;
        if (event.action == GLFW_PRESS) {
          dragging_[size_t(event.code)] = !io.WantCaptureMouse && !over_panel(mouse_x_, mouse_y_);
        } else {
          if (dragging_[size_t(event.code)]) log_line("drag " + std::to_string(event.code));
          dragging_[size_t(event.code)] = false;
        }
        break;
      case InputEvent::Kind::cursor:
        drag(float(event.x - mouse_x_), float(event.y - mouse_y_));
        mouse_x_ = event.x;
        mouse_y_ = event.y;
        break;
      case InputEvent::Kind::scroll:
        if (scene_ && !io.WantCaptureMouse)
          zoom(camera_, std::pow(0.9f, float(event.y)), accel_.get());
        break;
      case InputEvent::Kind::drop:
        if (!event.paths.empty()) open_scene(event.paths.front());
        break;
    }
  }

  bool over_panel(double x, double y) const {
    return panel_shown_ && x >= panel_pos_.x && x < panel_pos_.x + panel_size_.x &&
           y >= panel_pos_.y && y < panel_pos_.y + panel_size_.y;
  }

  void drag(float dx, float dy) {
    if (!scene_) return;
    const bool left = dragging_[GLFW_MOUSE_BUTTON_LEFT];
    const bool right = dragging_[GLFW_MOUSE_BUTTON_RIGHT];
    const float scale = std::max(renderer_.scene().bounds().diagonal(), 1e-3f);
    if (fly_mode_ && (left || right)) look(camera_, dx * 0.004f, -dy * 0.004f);
    if (!fly_mode_ && left) orbit(camera_, dx * 0.006f, dy * 0.006f, accel_.get());
    if (!fly_mode_ && right) fly(camera_, vec3(0.0f, -dx, dy) * (0.0015f * scale));
  }

  // A key pressed outside ImGui's text fields: each tap acts once, however slow the frame.
  void key_tap(int key, int mods) {
    if (key == GLFW_KEY_H) {
      hq_on_ = !hq_on_;
      log_action(key, hq_on_ ? "HQ on" : "HQ off");
    } else if (key == GLFW_KEY_TAB) {
      panel_shown_ = !panel_shown_;
      log_action(key, panel_shown_ ? "panel shown" : "panel hidden");
    } else if (key == GLFW_KEY_R && scene_) {
      log_action(key, "reload");
      open_scene(scene_path_);
    } else if (key == GLFW_KEY_Q && (mods & GLFW_MOD_CONTROL)) {
      log_action(key, "close");
      glfwSetWindowShouldClose(window_, 1);
    } else if (key == GLFW_KEY_F) {
      if (scene_) fit();
      log_action(key, scene_ ? "fit" : "no scene");
    } else if (key >= GLFW_KEY_1 && key < GLFW_KEY_1 + kFigure8PresetCount) {
      settings_ = figure8_preset(key - GLFW_KEY_1, settings_);
      log_action(key, figure8_preset_name(key - GLFW_KEY_1));
    }
  }

  // --log-actions: a line per key tap or drag on the view with what it did and the camera
  // after it (tests drive the window with xdotool and read these).
  void log_action(int key, const std::string& what) const {
    if (!options_.log_actions) return;
    const char* name = glfwGetKeyName(key, 0);
    log_line("key " +
             (name                  ? std::string(name)
              : key == GLFW_KEY_TAB ? "tab"
                                    : std::to_string(key)) +
             ": " + what);
  }

  void log_line(const std::string& what) const {
    if (!options_.log_actions) return;
    std::printf("%s; eye %.4f %.4f %.4f target %.4f %.4f %.4f\n", what.c_str(),
                double(camera_.position.x), double(camera_.position.y), double(camera_.position.z),
                double(camera_.target.x), double(camera_.target.y), double(camera_.target.z));
    std::fflush(stdout);
  }

  void handle_fly_keys(float dt) {
    if (!scene_ || !fly_mode_ || ImGui::GetIO().WantCaptureKeyboard) return;
    auto down = [&](int key) { return held_keys_.count(key) ? 1.0f : 0.0f; };
    const float scale = std::max(renderer_.scene().bounds().diagonal(), 1e-3f);
    const vec3 move{down(GLFW_KEY_W) - down(GLFW_KEY_S), down(GLFW_KEY_D) - down(GLFW_KEY_A),
                    down(GLFW_KEY_E) - down(GLFW_KEY_Q)};
    fly(camera_, move * (0.3f * scale * dt * (1.0f + 3.0f * down(GLFW_KEY_LEFT_SHIFT))));
  }

  void fit() {
    camera_ = fit_to_scene(renderer_.scene().bounds(), camera_.vertical_fov_deg, accel_.get());
  }

  // ---- the panel --------------------------------------------------------------------------
  // Sized to its content (ImGui's auto-resize), so no label is ever cut: every widget is
  // kItemWidthEm font heights wide and the labels are short, which keeps the panel at about a
  // quarter of a 1024-pixel window; taller than the window, it scrolls. Tab hides it, its
  // title bar's arrow collapses it.
  static constexpr float kItemWidthEm = 8.0f;

  void panel() {
    const float margin = 8.0f;
    const ImVec2 display = ImGui::GetIO().DisplaySize;
    ImGui::SetNextWindowPos(ImVec2(margin, margin), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSizeConstraints(ImVec2(0, 0),
                                        ImVec2(display.x - 2 * margin, display.y - 2 * margin));
    ImGui::Begin("lightbake (Tab hides)", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
    ImGui::PushItemWidth(kItemWidthEm * ImGui::GetFontSize());
    file_panel();  // first, so its field stays in place whatever the lines below say
    ImGui::PushTextWrapPos(0.0f);  // long paths and errors wrap at the panel's edge
    ImGui::TextWrapped("%s",
                       loading_.valid() ? ("loading " + loading_path_).c_str() : status_.c_str());
    if (!error_.empty()) ImGui::TextColored(ImVec4(1, 0.4f, 0.4f, 1), "%s", error_.c_str());
    ImGui::PopTextWrapPos();
    ImGui::Text("%.1f ms/frame", double(frame_ms_));
    if (scene_) {
      const FrameStats& stats = renderer_.stats();
      ImGui::Text("%zu triangles, %zu lights", triangle_count(renderer_.scene().scene()),
                  renderer_.scene().lights().lights.size());
      ImGui::Text("%d shadow cubes of %d^2 texels", stats.shadow_cubes,
                  stats.shadow_resolution.resolution);
      if (!stats.shadow_resolution.caster.empty()) {
        ImGui::Text("  for '%s', %.1f mm thick%s", stats.shadow_resolution.caster.c_str(),
                    1000.0f * stats.shadow_resolution.thickness,
                    stats.shadow_resolution.capped ? " (memory-capped)" : "");
      }
      if (stats.planar_passes > 0) ImGui::Text("%d mirror passes", stats.planar_passes);
      if (!renderer_.scene().scene().lights.empty()) {
        ImGui::Text("%zu lamps, %d shadow layers", renderer_.scene().scene().lights.size(),
                    stats.lamp_shadow_layers);
      }
      if (stats.lamps_unshadowed > 0) {
        ImGui::TextColored(ImVec4(1, 0.8f, 0.3f, 1), "%d lamps unshadowed (max %d)",
                           stats.lamps_unshadowed, kMaxShadowedLamps);
      }
    }
    bake_panel();
    hq_panel();
    export_panel();
    view_panel();
    camera_panel();
    light_panel();
    if (scene_ && group_mix_.panel()) upload(false);  // a group's weight moved: no rebake
    ImGui::PopItemWidth();
    // What the panel covers: a press there is the panel's even before ImGui has seen the
    // cursor over it (its WantCaptureMouse lags a frame behind a move); tests and docs too.
    panel_size_ = ImGui::GetWindowSize();
    panel_pos_ = ImGui::GetWindowPos();
    ImGui::End();
  }

  // Open a scene by path (or drop it onto the window), reload the shown one (R; a save from
  // an editor reloads by itself).
  void file_panel() {
    if (!scene_) ImGui::SetNextItemOpen(true);  // nothing shown: the way to open something
    if (!ImGui::CollapsingHeader("File", ImGuiTreeNodeFlags_DefaultOpen)) return;
    const bool enter =
        ImGui::InputText("##open", open_path_, sizeof open_path_,
                         ImGuiInputTextFlags_EnterReturnsTrue | ImGuiInputTextFlags_AutoSelectAll);
    ImGui::SameLine();
    if (ImGui::Button("Open") || enter) open_scene(open_path_);
    if (!scene_) ImGui::BeginDisabled();
    if (ImGui::Button("Reload (R)")) open_scene(scene_path_);
    if (!scene_) ImGui::EndDisabled();
    ImGui::SameLine();
    ImGui::TextDisabled("or drop a file here");
  }

  void bake_panel() {
    if (!ImGui::CollapsingHeader("Bake", ImGuiTreeNodeFlags_DefaultOpen)) return;
    if (baking_) {
      ImGui::ProgressBar(float(bake_job_.fraction()), ImVec2(-1, 0), bake_progress_text().c_str());
      if (showing_partial_) ImGui::Text("partial result (upload %.0f ms)", double(upload_ms_));
      if (ImGui::Button("Cancel")) bake_job_.cancel();
    } else {
      ImGui::Text("%s", bake_ ? "baked" : "not baked: direct only");
      if (scene_ && ImGui::Button("Bake")) start_bake();
    }
    // One knob first: a level sets the settings listed first below it (bake/pipeline/bake.h).
    int level = int(quality_);
    if (scene_ && ImGui::Combo("quality", &level, "draft\0standard\0high\0final\0")) {
      quality_ = Quality(level);
      apply_quality(*scene_, quality_, options_.bake);
    }
    bake_settings_panel(options_.bake);  // the same table of settings as the command line
  }

  void export_panel() {
    if (!ImGui::CollapsingHeader("Export")) return;
    ImGui::InputText("file", export_path_, sizeof export_path_);
    export_settings_panel();
    if (exporting_) {
      ImGui::ProgressBar(float(export_job_.fraction()), ImVec2(-1, 0), export_job_.stage().c_str());
      if (ImGui::Button("Cancel##export")) export_job_.cancel();
    } else {
      const bool ready = scene_ && !baking_;
      if (!ready) ImGui::BeginDisabled();
      if (ImGui::Button("Export glTF")) start_export();
      if (!ready) ImGui::EndDisabled();
      ImGui::SameLine();
      ImGui::TextDisabled("%s", baking_ ? "after the bake"
                                : bake_ ? "the shown bake"
                                        : "bakes first");
    }
    if (!export_error_.empty()) {
      ImGui::PushTextWrapPos(0.0f);
      ImGui::TextColored(ImVec4(1, 0.4f, 0.4f, 1), "%s", export_error_.c_str());
      ImGui::PopTextWrapPos();
    } else if (!export_done_.empty()) {
      ImGui::TextWrapped("%s", export_done_.c_str());
    }
  }

  // `lightbake export`'s choices, in its words (ExportSettings; checked when Export starts).
  void export_settings_panel() {
    ExportSettings& e = export_settings_;
    int contents = e.contents == "all" ? 1 : 0;
    if (ImGui::Combo("contents", &contents, "indirect\0all (+ direct light)\0"))
      e.contents = contents == 1 ? "all" : "indirect";
    int encoding = e.encoding == "rgbm" ? 1 : 0;
    if (ImGui::Combo("encoding", &encoding, "srgb\0rgbm\0"))
      e.encoding = encoding == 1 ? "rgbm" : "srgb";
    ImGui::Checkbox("denoise", &e.denoise);
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("contents all: the direct term through OIDN");
    ImGui::SameLine();
    ImGui::Checkbox("KTX2", &e.ktx2);
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("also as KTX2 with its mips (needs basisu)");
    ImGui::SameLine();
    ImGui::Checkbox("directional", &e.directional);
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("the L1 band (always where the view draws one)");
  }

  void view_panel() {
    if (!ImGui::CollapsingHeader("View", ImGuiTreeNodeFlags_DefaultOpen)) return;
    // Figure 8's four pictures in a row (keys 1-4), their names as tooltips.
    for (int i = 0; i < kFigure8PresetCount; ++i) {
      if (i > 0) ImGui::SameLine();
      if (ImGui::Button(std::to_string(i + 1).c_str())) settings_ = figure8_preset(i, settings_);
      if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", figure8_preset_name(i));
    }
    ImGui::SameLine();
    ImGui::TextDisabled("figure 8");
    int term = int(settings_.term);
    const auto names = term_names();
    if (ImGui::BeginCombo("output", names[size_t(term)].c_str())) {
      for (size_t i = 0; i < names.size(); ++i) {
        if (ImGui::Selectable(names[i].c_str(), int(i) == term)) settings_.term = Term(i);
      }
      ImGui::EndCombo();
    }
    ImGui::Checkbox("direct", &settings_.direct);
    ImGui::SameLine();
    ImGui::Checkbox("shadows", &settings_.shadows);
    ImGui::Checkbox("radiosity", &settings_.radiosity);
    ImGui::SameLine();
    ImGui::Checkbox("caustic maps", &settings_.caustics);
    ImGui::Checkbox("constant ambient", &settings_.ambient);
    // One light's shadows a fragment while the camera moves, exact again once it rests.
    bool stochastic = settings_.direct_mode == DirectMode::stochastic;
    if (ImGui::Checkbox("one shadow a pixel", &stochastic))
      settings_.direct_mode = stochastic ? DirectMode::stochastic : DirectMode::full;
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip(
          "stochastic direct light: frames of a still camera refine to the full "
          "image (%d still frames)",
          renderer_.accumulated_frames());
    if (settings_.ambient)
      ImGui::ColorEdit3("ambient E/pi", &settings_.ambient_radiance.x,
                        ImGuiColorEditFlags_Float | ImGuiColorEditFlags_HDR);
    ImGui::SliderFloat("exposure (stops)", &settings_.tone.exposure, -10.0f, 10.0f);
    const char* curves[] = {"clamp", "reinhard", "aces"};
    int curve = int(settings_.tone.curve);
    if (ImGui::Combo("tone curve", &curve, curves, 3)) settings_.tone.curve = ToneCurve(curve);
  }

  void camera_panel() {
    if (!ImGui::CollapsingHeader("Camera") || !scene_) return;
    ImGui::RadioButton("orbit", reinterpret_cast<int*>(&fly_mode_int_), 0);
    ImGui::SameLine();
    ImGui::RadioButton("fly (WASD QE)", reinterpret_cast<int*>(&fly_mode_int_), 1);
    fly_mode_ = fly_mode_int_ == 1;
    ImGui::SliderFloat("fov", &camera_.vertical_fov_deg, 10.0f, 120.0f);
    ImGui::Checkbox("full res. while moving", &full_resolution_only_);
    if (ImGui::Button("fit (F)")) fit();
    ImGui::SameLine();
    if (ImGui::Button("save view")) saved_views_.push_back(camera_);
    for (size_t i = 0; i < saved_views_.size(); ++i) {
      const std::string label = i < scene_->cameras.size()
                                    ? "camera '" + scene_->cameras[i].name + "'"
                                    : "saved view " + std::to_string(i);
      if (ImGui::Selectable(label.c_str())) camera_ = saved_views_[i];
    }
  }

  // Light colour and intensity: direct light changes at once, the maps are rebaked.
  void light_panel() {
    if (!ImGui::CollapsingHeader("Lights") || !scene_) return;
    bool changed = false, released = false;
    for (size_t m = 0; m < scene_->materials.size(); ++m) {
      Material& material = scene_->materials[m];
      if (!material.is_emitter()) continue;
      ImGui::PushID(int(m));
      float intensity = std::max({material.emission.x, material.emission.y, material.emission.z});
      vec3 colour = material.emission / intensity;
      ImGui::Text("%s", material.name.c_str());
      if (ImGui::ColorEdit3("colour", &colour.x)) changed = true;
      released |= ImGui::IsItemDeactivatedAfterEdit();
      if (ImGui::DragFloat("radiance", &intensity, intensity * 0.01f + 1e-3f, 1e-3f, 1e6f))
        changed = true;
      released |= ImGui::IsItemDeactivatedAfterEdit();
      if (changed) material.emission = glm::max(colour, vec3(1e-4f)) * intensity;
      ImGui::PopID();
    }
    if (changed && group_mix_.active()) upload(false);  // the groups weigh the new colours
    if (changed && !group_mix_.active()) renderer_.update_scene(*scene_, bake_ ? &*bake_ : nullptr);
    if (released) start_bake();
  }

  // The shown bake's light groups at the command line's weights (a bad name: the panel's
  // error line, and every group at 1).
  void reset_groups() {
    try {
      group_mix_.reset(*scene_, bake_ ? &*bake_ : nullptr, options_.group_weights);
    } catch (const std::invalid_argument& e) {
      error_ = e.what();
      std::fprintf(stderr, "lightbake: error: %s\n", e.what());
      group_mix_.reset(*scene_, bake_ ? &*bake_ : nullptr, "");
    }
  }

  // The scene and bake to the renderers (`full`: set_scene, else update_scene), the light
  // groups weighed when the bake has any.
  void upload(bool full) {
    const Scene* scene = scene_.get();
    const BakeResult* bake = bake_ ? &*bake_ : nullptr;
    if (bake && group_mix_.active()) {
      group_mix_.apply(*scene_, *bake_);
      scene = &group_mix_.scene();
      bake = &group_mix_.bake();
    }
    if (full)
      renderer_.set_scene(*scene, bake, options_.shadows);
    else
      renderer_.update_scene(*scene, bake);
    hq_.set_bake(*scene, bake);
  }

  GLFWwindow* window_;
  WindowInput& input_;
  ViewerOptions options_;
  RenderSettings settings_;
  Renderer renderer_;
  HqView hq_;
  bool hq_on_ = false;
  bool hq_automation_done_ = false;
  int hq_frames_ = 0;    // automation: frames drawn while waiting for the HQ passes
  Camera start_camera_;  // the scene camera the view starts from (HQ renders with its lens)
  std::future<LoadedScene> loading_;
  Load loading_kind_ = Load::first;
  std::string loading_path_;
  std::optional<std::pair<std::string, Load>> pending_load_;  // asked for while loading
  std::string scene_path_;                                    // the shown scene's file
  FileWatch watch_;
  std::chrono::steady_clock::time_point next_file_check_;
  char open_path_[1024] = {};
  std::unique_ptr<Scene> scene_;
  std::unique_ptr<Accel> accel_;  // over *scene_: declared after it, destroyed before it
  std::optional<BakeResult> bake_;
  LightGroupMix group_mix_;  // the bake's light groups and the panel's weights
  Quality quality_ = Quality::standard;  // the panel's level
  BakeJob bake_job_;
  bool baking_ = false;
  ExportJob export_job_;
  bool exporting_ = false;
  bool export_requested_ = false;  // automation: the Export press was made
  char export_path_[1024] = {};
  ExportSettings export_settings_ = options_.export_settings;  // the panel's choices
  std::string export_error_, export_done_;
  bool showing_partial_ = false;  // the renderer holds a partial bake
  std::optional<RadiosityStats> partial_stats_;
  float upload_ms_ = 0.0f;
  std::chrono::steady_clock::time_point next_upload_;
  int partials_shown_ = 0;
  ViewCamera camera_;
  std::vector<ViewCamera> saved_views_;
  bool fly_mode_ = false;
  bool panel_shown_ = true;
  bool text_input_ = false;        // an ImGui text field has the keyboard
  ImVec2 panel_pos_, panel_size_;  // the panel's last rectangle, pixels
  std::set<int> held_keys_;        // pressed outside ImGui and not yet released
  std::array<bool, GLFW_MOUSE_BUTTON_LAST + 1> dragging_{};  // pressed on the view
  bool camera_moved_ = false;
  std::chrono::steady_clock::time_point last_move_;  // the camera's last move (HQ waits)
  int moving_divisor_ = 2;
  int raster_divisor_ = 0, raster_width_ = 0, raster_height_ = 0;  // the last raster frame
  std::chrono::steady_clock::time_point next_raster_;
  bool full_resolution_only_ = false;
  int fly_mode_int_ = 0;
  double mouse_x_ = 0, mouse_y_ = 0;
  float frame_ms_ = 0.0f;
  int frames_shown_ = 0;
  int exit_status_ = 0;
  std::string status_, error_;
};

}  // namespace

int run_viewer(const ViewerOptions& options) {
  glfwSetErrorCallback(
      [](int, const char* message) { std::fprintf(stderr, "lightbake: GLFW: %s\n", message); });
  if (!glfwInit()) {
    std::fprintf(stderr, "lightbake: error: cannot open a window (no display?)\n");
    return 1;
  }
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);
  GLFWwindow* window =
      glfwCreateWindow(options.width, options.height, ("lightbake - " + options.scene_path).c_str(),
                       nullptr, nullptr);
  if (!window) {
    std::fprintf(stderr, "lightbake: error: cannot create an OpenGL 3.3 core window\n");
    glfwTerminate();
    return 1;
  }
  glfwMakeContextCurrent(window);
  glfwSwapInterval(options.frames > 0 ? 0 : 1);
  int status = 1;
  try {
    load_gl(reinterpret_cast<GlProcLoader>(glfwGetProcAddress));
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini next to the user's files
    ImGui_ImplGlfw_InitForOpenGL(window, true);
    ImGui_ImplOpenGL3_Init("#version 330");
    {
      WindowInput input(window);  // over ImGui's callbacks, calling them
      ViewerApp app(window, input, options);
      status = app.run();
    }
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
  } catch (const std::exception& e) {
    print_message("error", e.what());
    status = 1;
  }
  glfwDestroyWindow(window);
  glfwTerminate();
  return status;
}

}  // namespace lb
