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

void BakeJob::start(const Scene& scene, const BakeParams& params) {
  cancel();
  join();
  cancel_ = false;
  running_ = true;
  fraction_ = 0.0;
  {
    std::lock_guard lock(mutex_);
    stage_ = "starting";
    error_.clear();
    result_.reset();
  }
  thread_ = std::thread([this, scene, params] {
    Progress progress;
    progress.cancel = &cancel_;
    progress.report = [this](std::string_view stage, double fraction) {
      fraction_ = fraction;
      std::lock_guard lock(mutex_);
      stage_ = std::string(stage);
    };
    try {
      BakeResult result = bake_scene(scene, params, progress);
      std::lock_guard lock(mutex_);
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
