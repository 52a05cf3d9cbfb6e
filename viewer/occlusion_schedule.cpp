#include "viewer/occlusion_schedule.h"

#include <algorithm>

namespace lb {

void OcclusionSchedule::frame_done(bool queried, double hidden, double in_view) {
  if (!queried) {
    wait_ = std::max(0, wait_ - 1);
    return;
  }
  if (hidden >= kWorthwhile * in_view && in_view > 0.0) {
    backoff_ = 0;
    wait_ = 0;
    return;
  }
  backoff_ = backoff_ == 0 ? kFirstWait : std::min(2 * backoff_, kMaxWait);
  wait_ = backoff_;
}

}  // namespace lb
