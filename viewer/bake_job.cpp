#include "viewer/bake_job.h"

namespace lb {

void BakeJob::start(const Scene& scene, const BakeParams& params, double partial_interval_seconds) {
  job_.stop();
  {
    std::lock_guard lock(mutex_);
    partial_.reset();
    result_.reset();
  }
  job_.start([this, scene, params, partial_interval_seconds](const Progress& progress) {
    BakeCallbacks callbacks;
    callbacks.min_interval_seconds = partial_interval_seconds;
    callbacks.on_partial = [this](const BakeResult& partial) {
      // Copy outside the lock and free the replaced (unseen) partial outside it too, so the
      // render thread never waits for more than a swap.
      std::optional<BakeResult> copy(partial);
      {
        std::lock_guard lock(mutex_);
        partial_.swap(copy);
      }
    };
    BakeResult result = bake_scene(scene, params, progress, callbacks);
    {
      std::lock_guard lock(mutex_);
      partial_.reset();  // superseded
      result_ = std::move(result);
    }
    job_.set_stage("done");
  });
}

std::optional<BakeResult> BakeJob::take_partial() {
  std::optional<BakeResult> partial;
  std::lock_guard lock(mutex_);
  partial.swap(partial_);
  return partial;
}

std::optional<BakeResult> BakeJob::take_result() {
  std::lock_guard lock(mutex_);
  std::optional<BakeResult> result = std::move(result_);
  result_.reset();
  return result;
}

}  // namespace lb
