#pragma once
// Progress of a long subcommand on stderr, and Ctrl-C as cancellation.

#include <csignal>

#include "bake/progress.h"

namespace lb::app {

// While alive, SIGINT sets the cancel flag of `progress()` instead of killing the process, so
// the work stops at its next check and throws lb::Cancelled with nothing half written.
// Reports print one line per stage, one every 10% and one every 10 s in between, with the time
// left: readable in a terminal and in logs.
class ConsoleProgress {
 public:
  explicit ConsoleProgress(bool quiet);
  ~ConsoleProgress();
  ConsoleProgress(const ConsoleProgress&) = delete;
  ConsoleProgress& operator=(const ConsoleProgress&) = delete;

  const Progress& progress() const { return progress_; }

 private:
  Progress progress_;
  void (*previous_handler_)(int) = SIG_DFL;
};

}  // namespace lb::app
