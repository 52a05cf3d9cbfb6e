#pragma once
// When the camera pass's occlusion queries run (Renderer::Culling::camera_occlusion). They pay
// inside a level (the walls hide most of it) and cost where nothing is hidden (from above, a
// cluster holds a room's ceiling and what lies under it alike): the box draws, and on llvmpipe
// every wait for their results drains the queue. So a frame queries when the last queried
// frame hid enough; otherwise the next frames draw without queries, more of them after each
// losing probe (kFirstWait, doubling up to kMaxWait), and then one probes again. Queries never
// change the image, so which frames query changes only the cost.

namespace lb {

class OcclusionSchedule {
 public:
  // Share of the in-view triangles a queried frame must hide to keep querying. Measured on
  // the 92k/1M levels: inside, about 90 % hidden and the frame 2-5x faster; from above, 6 %
  // hidden and the frame 1.2x slower.
  static constexpr double kWorthwhile = 0.25;
  static constexpr int kFirstWait = 4, kMaxWait = 32;

  // Whether this frame's pass should query.
  bool query() const { return wait_ == 0; }
  // After a frame: `queried` as query() said; then `hidden` of `in_view` triangles skipped.
  void frame_done(bool queried, double hidden, double in_view);
  void reset() { *this = OcclusionSchedule(); }
  int frames_to_wait() const { return wait_; }

 private:
  int wait_ = 0;      // frames left without queries
  int backoff_ = 0;   // the wait after the next losing probe / 2; 0 after a win
};

}  // namespace lb
