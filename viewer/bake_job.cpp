#include "viewer/bake_job.h"

#include <exception>

namespace lb {

BakeJob::~BakeJob() {
  cancel();
  join();
}

void BakeJob::join() {
  if (thread_.joinable()) thread_.join();
}

void BakeJob::start(const Scene& scene, const BakeParams& params, double partial_interval_seconds) {
  cancel();
  join();
  cancel_ = false;
  running_ = true;
  fraction_ = 0.0;
  {
    std::lock_guard lock(mutex_);
    stage_ = "starting";
    error_.clear();
    partial_.reset();
    result_.reset();
  }
  thread_ = std::thread([this, scene, params, partial_interval_seconds] {
    Progress progress;
    progress.cancel = &cancel_;
    progress.report = [this](std::string_view stage, double fraction) {
      fraction_ = fraction;
      std::lock_guard lock(mutex_);
      stage_ = std::string(stage);
    };
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
    try {
      BakeResult result = bake_scene(scene, params, progress, callbacks);
      std::lock_guard lock(mutex_);
      partial_.reset();  // superseded
      result_ = std::move(result);
      stage_ = "done";
    } catch (const Cancelled&) {
      std::lock_guard lock(mutex_);
      stage_ = "cancelled";
    } catch (const std::exception& e) {
      std::lock_guard lock(mutex_);
      error_ = e.what();
      stage_ = "failed";
    }
    running_ = false;
  });
}

void BakeJob::cancel() {
  cancel_ = true;
}

std::string BakeJob::stage() const {
  std::lock_guard lock(mutex_);
  return stage_;
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

std::string BakeJob::error() const {
  std::lock_guard lock(mutex_);
  return error_;
}

}  // namespace lb
