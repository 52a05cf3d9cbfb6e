#include "viewer/background_job.h"

#include <exception>
#include <utility>

namespace lb {

void BackgroundJob::stop() {
  cancel();
  if (thread_.joinable()) thread_.join();
}

void BackgroundJob::start(std::function<void(const Progress&)> work, std::string cancelled_stage) {
  stop();
  cancel_ = false;
  running_ = true;
  fraction_ = 0.0;
  {
    std::lock_guard lock(mutex_);
    stage_ = "starting";
    error_.clear();
  }
  thread_ = std::thread([this, work = std::move(work), cancelled_stage] {
    Progress progress;
    progress.cancel = &cancel_;
    progress.report = [this](std::string_view stage, double fraction) { report(stage, fraction); };
    try {
      work(progress);
    } catch (const Cancelled&) {
      set_stage(cancelled_stage);
    } catch (const std::exception& e) {
      fail(e.what(), "failed");
    }
    running_ = false;
  });
}

std::string BackgroundJob::stage() const {
  std::lock_guard lock(mutex_);
  return stage_;
}

std::string BackgroundJob::error() const {
  std::lock_guard lock(mutex_);
  return error_;
}

void BackgroundJob::report(std::string_view stage, double fraction) {
  fraction_ = fraction;
  set_stage(stage);
}

void BackgroundJob::set_stage(std::string_view stage) {
  std::lock_guard lock(mutex_);
  stage_ = std::string(stage);
}

void BackgroundJob::fail(std::string error, std::string_view stage) {
  std::lock_guard lock(mutex_);
  error_ = std::move(error);
  stage_ = std::string(stage);
}

}  // namespace lb
