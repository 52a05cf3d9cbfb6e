#include "viewer/window_viewer.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <future>
#include <optional>
#include <string>
#include <vector>

#include "viewer/renderer.h"  // glad first: GLFW and ImGui's backend must not include GL

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include "bake/camera.h"
#include "bake/io/gltf_bake_read.h"
#include "bake/io/gltf_export.h"
#include "bake/io/image_io.h"
#include "bake/io/scene_load.h"
#include "bake/pipeline/bake_io.h"
#include "viewer/bake_job.h"
#include "viewer/export_job.h"
#include "viewer/hq_view.h"
#include "viewer/snapshot.h"

namespace lb {

namespace {

struct LoadedScene {
  Scene scene;
  std::optional<BakeResult> bake;
  std::vector<std::string> warnings;
};

// Runs on a worker thread: parse, validate, and read the bake directory if there is one (or the
// baked light inside a glTF that `lightbake export` wrote).
LoadedScene load_everything(const ViewerOptions& options) {
  LoadedScene loaded;
  LoadResult result = load_scene(options.scene_path, options.load);
  loaded.scene = std::move(result.scene);
  loaded.warnings = std::move(result.warnings);
  if (!options.bake_dir.empty()) {
    loaded.bake = load_bake(options.bake_dir, loaded.scene);
  } else if (is_lightbake_gltf(options.scene_path)) {
    loaded.bake = read_gltf_bake(options.scene_path, loaded.scene);  // `lightbake export`'s light
  }
  return loaded;
}

class ViewerApp {
 public:
  ViewerApp(GLFWwindow* window, const ViewerOptions& options)
      : window_(window),
        options_(options),
        settings_(options.settings),
        renderer_(options.shader_directory),
        hq_(options.shader_directory),
        hq_on_(options.hq) {
    loading_ = std::async(std::launch::async, [options] { return load_everything(options); });
    status_ = "loading " + options.scene_path;
    set_export_path(default_export_path(options.scene_path));
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
            renderer_.render(camera_, std::max(1, width / divisor), std::max(1, height / divisor),
                             settings_);
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
      if (!options_.hide_panel) panel();
      ImGui::Render();
      ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
      if (width > 0 && height > 0 && !automation(width, height)) return exit_status_;
      glfwSwapBuffers(window_);
    }
    return exit_status_;
  }

 private:
  // ---- background work ------------------------------------------------------------------
  bool poll_loading() {
    if (!loading_.valid() ||
        loading_.wait_for(std::chrono::seconds(0)) != std::future_status::ready)
      return true;
    try {
      LoadedScene loaded = loading_.get();
      for (const auto& warning : loaded.warnings)
        std::fprintf(stderr, "lightbake: warning: %s\n", warning.c_str());
      scene_ = std::move(loaded.scene);
      bake_ = std::move(loaded.bake);
      renderer_.set_scene(*scene_, bake_ ? &*bake_ : nullptr, options_.shadows);
      hq_.set_bake(*scene_, bake_ ? &*bake_ : nullptr);
      start_camera_ = select_camera(*scene_, options_.camera);
      camera_ = ViewCamera::from(start_camera_);
      if (options_.exposure_from_camera)
        settings_.tone.exposure = select_camera(*scene_, options_.camera).exposure;
      for (const Camera& camera : scene_->cameras) saved_views_.push_back(ViewCamera::from(camera));
      status_ = options_.scene_path;
      quality_ = choose_quality(*scene_, options_.quality);
      apply_quality(*scene_, quality_, options_.bake);
      if (!bake_ && options_.bake_on_load) start_bake();
    } catch (const std::exception& e) {
      std::fprintf(stderr, "lightbake: error: %s\n", e.what());
      if (options_.frames > 0) return false;  // automation: fail instead of waiting
      error_ = e.what();
    }
    return true;
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
      renderer_.update_scene(*scene_, &*bake_);
      hq_.set_bake(*scene_, &*bake_);
      if (options_.frames > 0)  // automation: say how the bake refined on screen
        std::printf("baked: %d partial results shown, last upload %.1f ms\n", partials_shown_,
                    double(upload_ms_));
    } else {
      // Cancelled or failed: back to the last complete bake (or none).
      if (showing_partial_) renderer_.update_scene(*scene_, bake_ ? &*bake_ : nullptr);
      if (!bake_job_.error().empty()) {
        error_ = "bake failed: " + bake_job_.error();
        std::fprintf(stderr, "lightbake: error: %s\n", error_.c_str());
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
        std::fprintf(stderr, "lightbake: error: HQ mode: %s\n", hq_.error().c_str());
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
    if (!ImGui::CollapsingHeader("HQ ray tracing", ImGuiTreeNodeFlags_DefaultOpen)) return;
    ImGui::Checkbox("HQ (H)", &hq_on_);
    ImGui::SameLine();
    ImGui::TextDisabled("refines while the view rests");
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
  // in the text field; a refusal or failure becomes the panel's error line.
  void start_export() {
    if (!scene_ || baking_ || exporting_) return;
    export_error_.clear();
    export_done_.clear();
    if (export_job_.start(export_path_, *scene_, bake_ ? &*bake_ : nullptr, options_.bake)) {
      exporting_ = true;
    } else {
      export_error_ = export_job_.error();
      std::fprintf(stderr, "lightbake: error: %s\n", export_error_.c_str());
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
      std::printf("exported %s (%zu bytes)\n", export_path_, info->bytes);
    } else if (!export_job_.error().empty()) {
      export_error_ = export_job_.error();
      std::fprintf(stderr, "lightbake: error: %s\n", export_error_.c_str());
    } else {
      export_done_ = export_job_.stage();  // cancelled
    }
  }

  // ---- input ------------------------------------------------------------------------------
  void handle_input(float dt) {
    const ViewCamera before = camera_;
    handle_camera_input(dt);
    camera_moved_ = before.position != camera_.position || before.target != camera_.target ||
                    before.vertical_fov_deg != camera_.vertical_fov_deg;
    if (camera_moved_) last_move_ = std::chrono::steady_clock::now();
  }

  void handle_camera_input(float dt) {
    const ImGuiIO& io = ImGui::GetIO();
    double x = 0, y = 0;
    glfwGetCursorPos(window_, &x, &y);
    const float dx = float(x - mouse_x_), dy = float(y - mouse_y_);
    mouse_x_ = x;
    mouse_y_ = y;
    if (!scene_) return;
    const float scale = std::max(renderer_.scene().bounds().diagonal(), 1e-3f);
    if (!io.WantCaptureMouse) {
      const bool left = glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
      const bool right = glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS;
      if (fly_mode_ && (left || right)) look(camera_, dx * 0.004f, -dy * 0.004f);
      if (!fly_mode_ && left) orbit(camera_, dx * 0.006f, dy * 0.006f);
      if (!fly_mode_ && right) fly(camera_, vec3(0.0f, -dx, dy) * (0.0015f * scale));
      if (scroll_ != 0.0f) zoom(camera_, std::pow(0.9f, scroll_));
    }
    scroll_ = 0.0f;
    if (io.WantCaptureKeyboard) return;
    auto down = [&](int key) { return glfwGetKey(window_, key) == GLFW_PRESS ? 1.0f : 0.0f; };
    if (fly_mode_) {
      const vec3 move{down(GLFW_KEY_W) - down(GLFW_KEY_S), down(GLFW_KEY_D) - down(GLFW_KEY_A),
                      down(GLFW_KEY_E) - down(GLFW_KEY_Q)};
      fly(camera_, move * (0.3f * scale * dt * (1.0f + 3.0f * down(GLFW_KEY_LEFT_SHIFT))));
    }
    if (down(GLFW_KEY_F) > 0)
      camera_ = fit_to_scene(renderer_.scene().bounds(), camera_.vertical_fov_deg);
    for (int i = 0; i < kFigure8PresetCount; ++i) {
      if (down(GLFW_KEY_1 + i) > 0) settings_ = figure8_preset(i, settings_);
    }
  }

 public:
  void add_scroll(float amount) { scroll_ += amount; }
  // Key taps through GLFW's callback, so none is lost at a low frame rate.
  void key(int key, int action) {
    if (action != GLFW_PRESS || ImGui::GetIO().WantCaptureKeyboard) return;
    if (key == GLFW_KEY_H) hq_on_ = !hq_on_;
  }

 private:
  // ---- the panel --------------------------------------------------------------------------
  void panel() {
    ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(330, 0), ImGuiCond_FirstUseEver);
    ImGui::Begin("lightbake");
    ImGui::TextWrapped("%s", status_.c_str());
    if (!error_.empty()) ImGui::TextColored(ImVec4(1, 0.4f, 0.4f, 1), "%s", error_.c_str());
    ImGui::Text("%.1f ms/frame", double(frame_ms_));
    if (scene_) {
      ImGui::Text("%zu triangles, %zu lights, %d shadow cubes",
                  triangle_count(renderer_.scene().scene()),
                  renderer_.scene().lights().lights.size(), renderer_.stats().shadow_cubes);
      const FrameStats& stats = renderer_.stats();
      if (!renderer_.scene().scene().lights.empty()) {
        ImGui::Text("%zu lamps, %d lamp shadow layers", renderer_.scene().scene().lights.size(),
                    stats.lamp_shadow_layers);
      }
      if (stats.lamps_unshadowed > 0) {
        ImGui::TextColored(ImVec4(1, 0.8f, 0.3f, 1), "%d lamps without shadows (max %d)",
                           stats.lamps_unshadowed, kMaxShadowedLamps);
      }
    }
    bake_panel();
    hq_panel();
    export_panel();
    view_panel();
    camera_panel();
    light_panel();
    ImGui::End();
  }

  void bake_panel() {
    if (!ImGui::CollapsingHeader("Bake", ImGuiTreeNodeFlags_DefaultOpen)) return;
    if (baking_) {
      ImGui::ProgressBar(float(bake_job_.fraction()), ImVec2(-1, 0), bake_progress_text().c_str());
      if (showing_partial_)
        ImGui::Text("showing partial result (upload %.1f ms)", double(upload_ms_));
      if (ImGui::Button("Cancel")) bake_job_.cancel();
    } else {
      ImGui::Text("%s", bake_ ? "baked" : "not baked (direct light only)");
      if (scene_ && ImGui::Button("Bake")) start_bake();
    }
    // One knob first: a level sets the three settings below it (bake/pipeline/bake.h).
    int level = int(quality_);
    if (scene_ && ImGui::Combo("quality", &level, "draft\0standard\0high\0final\0")) {
      quality_ = Quality(level);
      apply_quality(*scene_, quality_, options_.bake);
    }
    // The same params structs as the `bake` command.
    auto& ill = options_.bake.illumination;
    auto& rad = options_.bake.radiosity;
    // Typed values are clamped too (ImGui lets Ctrl+click input leave the range otherwise).
    const ImGuiSliderFlags clamp = ImGuiSliderFlags_AlwaysClamp;
    ImGui::DragInt("rays per zone side", &ill.rays_per_zone_side, 1, 4, 1024, "%d", clamp);
    ImGui::DragFloat("map texel (m, 0 auto)", &ill.texel_size, 0.001f, 0.0f, 1.0f, "%.3f", clamp);
    ImGui::DragFloat("patch size (m, 0 auto)", &rad.patch_size, 0.01f, 0.0f, 10.0f, "%.3f", clamp);
    int budget_k = int(rad.ray_budget / 1000);
    if (ImGui::DragInt("radiosity rays (k)", &budget_k, 10, 1, 1000000, "%d", clamp))
      rad.ray_budget = uint64_t(budget_k) * 1000;
    int seed = int(options_.bake.seed);
    if (ImGui::InputInt("seed", &seed)) options_.bake.seed = uint64_t(std::max(seed, 0));
  }

  void export_panel() {
    if (!ImGui::CollapsingHeader("Export", ImGuiTreeNodeFlags_DefaultOpen)) return;
    ImGui::InputText("file", export_path_, sizeof export_path_);
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

  void view_panel() {
    if (!ImGui::CollapsingHeader("View", ImGuiTreeNodeFlags_DefaultOpen)) return;
    for (int i = 0; i < kFigure8PresetCount; ++i) {
      if (ImGui::Button((std::to_string(i + 1) + ": " + figure8_preset_name(i)).c_str()))
        settings_ = figure8_preset(i, settings_);
    }
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
    ImGui::Checkbox("full resolution while moving", &full_resolution_only_);
    if (ImGui::Button("fit to scene (F)"))
      camera_ = fit_to_scene(renderer_.scene().bounds(), camera_.vertical_fov_deg);
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
    if (changed) renderer_.update_scene(*scene_, bake_ ? &*bake_ : nullptr);
    if (released) start_bake();
  }

  GLFWwindow* window_;
  ViewerOptions options_;
  RenderSettings settings_;
  Renderer renderer_;
  HqView hq_;
  bool hq_on_ = false;
  bool hq_automation_done_ = false;
  int hq_frames_ = 0;    // automation: frames drawn while waiting for the HQ passes
  Camera start_camera_;  // the scene camera the view starts from (HQ renders with its lens)
  std::future<LoadedScene> loading_;
  std::optional<Scene> scene_;
  std::optional<BakeResult> bake_;
  Quality quality_ = Quality::standard;  // the panel's level
  BakeJob bake_job_;
  bool baking_ = false;
  ExportJob export_job_;
  bool exporting_ = false;
  bool export_requested_ = false;  // automation: the Export press was made
  char export_path_[1024] = {};
  std::string export_error_, export_done_;
  bool showing_partial_ = false;  // the renderer holds a partial bake
  std::optional<RadiosityStats> partial_stats_;
  float upload_ms_ = 0.0f;
  std::chrono::steady_clock::time_point next_upload_;
  int partials_shown_ = 0;
  ViewCamera camera_;
  std::vector<ViewCamera> saved_views_;
  bool fly_mode_ = false;
  bool camera_moved_ = false;
  std::chrono::steady_clock::time_point last_move_;  // the camera's last move (HQ waits)
  int moving_divisor_ = 2;
  int raster_divisor_ = 0, raster_width_ = 0, raster_height_ = 0;  // the last raster frame
  std::chrono::steady_clock::time_point next_raster_;
  bool full_resolution_only_ = false;
  int fly_mode_int_ = 0;
  double mouse_x_ = 0, mouse_y_ = 0;
  float scroll_ = 0.0f;
  float frame_ms_ = 0.0f;
  int frames_shown_ = 0;
  int exit_status_ = 0;
  std::string status_, error_;
};

void scroll_callback(GLFWwindow* window, double x, double y) {
  ImGui_ImplGlfw_ScrollCallback(window, x, y);
  if (auto* app = static_cast<ViewerApp*>(glfwGetWindowUserPointer(window)))
    app->add_scroll(float(y));
}

void key_callback(GLFWwindow* window, int key, int scancode, int action, int mods) {
  ImGui_ImplGlfw_KeyCallback(window, key, scancode, action, mods);
  if (auto* app = static_cast<ViewerApp*>(glfwGetWindowUserPointer(window))) app->key(key, action);
}

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
    glfwSetScrollCallback(window, scroll_callback);
    glfwSetKeyCallback(window, key_callback);
    ImGui_ImplOpenGL3_Init("#version 330");
    {
      ViewerApp app(window, options);
      glfwSetWindowUserPointer(window, &app);
      status = app.run();
      glfwSetWindowUserPointer(window, nullptr);
    }
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "lightbake: error: %s\n", e.what());
    status = 1;
  }
  glfwDestroyWindow(window);
  glfwTerminate();
  return status;
}

}  // namespace lb
