#pragma once
// A bake on a background thread, so the window keeps drawing: start, progress, cancel, the
// partial results as the bake refines (only the newest is kept) and the final result, each
// picked up by the render thread when it polls.

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

  // Cancels and waits for any running bake, then starts baking a copy of `scene`, handing
  // out partial results at most every `partial_interval_seconds`.
  void start(const Scene& scene, const BakeParams& params, double partial_interval_seconds = 0.25);
  void cancel();  // asks the bake to stop; it ends at its next progress check
  bool running() const { return running_.load(); }
  double fraction() const { return fraction_.load(); }
  std::string stage() const;
  // The newest partial result not yet taken, once (older ones were dropped unseen).
  std::optional<BakeResult> take_partial();
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
  std::optional<BakeResult> partial_;
  std::optional<BakeResult> result_;
};

}  // namespace lb
