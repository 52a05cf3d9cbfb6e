#pragma once
// A bake on a background thread, so the window keeps drawing: start, progress, cancel, the
// partial results as the bake refines (only the newest is kept) and the final result, each
// picked up by the render thread when it polls.

#include <mutex>
#include <optional>
#include <string>

#include "bake/pipeline/bake.h"
#include "viewer/background_job.h"

namespace lb {

class BakeJob {
 public:
  // Cancels and waits for any running bake, then starts baking a copy of `scene`, handing
  // out partial results at most every `partial_interval_seconds`.
  void start(const Scene& scene, const BakeParams& params, double partial_interval_seconds = 0.25);
  void cancel() { job_.cancel(); }  // the bake ends at its next progress check
  bool running() const { return job_.running(); }
  double fraction() const { return job_.fraction(); }
  std::string stage() const { return job_.stage(); }
  // The newest partial result not yet taken, once (older ones were dropped unseen).
  std::optional<BakeResult> take_partial();
  // The finished bake, once (empty while running, after cancel and after an error).
  std::optional<BakeResult> take_result();
  std::string error() const { return job_.error(); }  // the last failure, or empty

 private:
  mutable std::mutex mutex_;
  std::optional<BakeResult> partial_;
  std::optional<BakeResult> result_;
  BackgroundJob job_;  // last: joined before the results above are destroyed
};

}  // namespace lb
