#pragma once
// Progress reporting and cancellation for long work (bake passes, renders).
// The CLI prints it, the viewer draws a bar, tests ignore it.

#include <atomic>
#include <functional>
#include <stdexcept>
#include <string_view>

namespace lb {

struct Progress {
  // Called with the current stage name and the fraction done in [0,1]; may be empty.
  std::function<void(std::string_view stage, double fraction)> report;
  // Set from another thread to stop work; passes then throw `Cancelled`.
  const std::atomic<bool>* cancel = nullptr;

  void update(std::string_view stage, double fraction) const {
    if (report) report(stage, fraction);
  }
  bool cancelled() const { return cancel && cancel->load(std::memory_order_relaxed); }
  void throw_if_cancelled() const;
};

struct Cancelled : std::runtime_error {
  Cancelled() : std::runtime_error("cancelled") {}
};

inline void Progress::throw_if_cancelled() const {
  if (cancelled()) throw Cancelled();
}

}  // namespace lb
