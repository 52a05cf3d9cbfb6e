#pragma once
// A bake on a background thread, so the window keeps drawing: start, progress, cancel, and
// the result picked up by the render thread when it is done.

#include <atomic>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "bake/pipeline/bake.h"

namespace lb {

class BakeJob {
 public:
  BakeJob() = default;
  ~BakeJob();
  BakeJob(const BakeJob&) = delete;
  BakeJob& operator=(const BakeJob&) = delete;

  // Cancels and waits for any running bake, then starts baking a copy of `scene`.
  void start(const Scene& scene, const BakeParams& params);
  void cancel();  // asks the bake to stop; it ends at its next progress check
  bool running() const { return running_.load(); }
  double fraction() const { return fraction_.load(); }
  std::string stage() const;
  // The finished bake, once (empty while running, after cancel and after an error).
  std::optional<BakeResult> take_result();
  std::string error() const;  // the last failure, or empty

 private:
  void join();

  std::thread thread_;
  std::atomic<bool> cancel_{false};
  std::atomic<bool> running_{false};
  std::atomic<double> fraction_{0.0};
  mutable std::mutex mutex_;
  std::string stage_;
  std::string error_;
  std::optional<BakeResult> result_;
};

}  // namespace lb
