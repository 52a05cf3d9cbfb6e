#pragma once
// What the viewer's background jobs (BakeJob, ExportJob) share: one worker thread, the cancel
// flag its Progress reads, and the stage, fraction and last error that the render thread reads
// when it polls. An owner declares its BackgroundJob member last, so it is destroyed (cancelled
// and joined) before the results the thread writes into.

#include <atomic>
#include <functional>
#include <mutex>
#include <string>
#include <string_view>
#include <thread>

#include "bake/progress.h"

namespace lb {

class BackgroundJob {
 public:
  BackgroundJob() = default;
  ~BackgroundJob() { stop(); }
  BackgroundJob(const BackgroundJob&) = delete;
  BackgroundJob& operator=(const BackgroundJob&) = delete;

  // Cancels and waits for any running work.
  void stop();
  // stop(), then runs `work` on a new thread with a Progress that reports into stage() and
  // fraction() and stops on cancel(). A thrown Cancelled sets the stage `cancelled_stage`;
  // another exception sets error() and the stage "failed".
  void start(std::function<void(const Progress&)> work, std::string cancelled_stage = "cancelled");
  void cancel() { cancel_ = true; }
  bool running() const { return running_.load(); }
  double fraction() const { return fraction_.load(); }
  std::string stage() const;
  std::string error() const;  // the last failure, or empty

  // From the work (or the owner): the stage text and the fraction done in [0,1].
  void report(std::string_view stage, double fraction);
  void set_stage(std::string_view stage);
  // A failure found before any work starts (a refused output path).
  void fail(std::string error, std::string_view stage);

 private:
  std::thread thread_;
  std::atomic<bool> cancel_{false};
  std::atomic<bool> running_{false};
  std::atomic<double> fraction_{0.0};
  mutable std::mutex mutex_;
  std::string stage_;
  std::string error_;
};

}  // namespace lb
