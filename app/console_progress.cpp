#include "app/console_progress.h"

#include <atomic>
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>

namespace lb::app {

namespace {
std::atomic<bool> interrupted{false};
extern "C" void on_interrupt(int) {
  interrupted = true;
}
}  // namespace

ConsoleProgress::ConsoleProgress(bool quiet) {
  interrupted = false;
  previous_handler_ = std::signal(SIGINT, on_interrupt);
  progress_.cancel = &interrupted;
  if (quiet) return;
  auto stage_seen = std::make_shared<std::string>();
  auto last_tenth = std::make_shared<int>(-1);
  const auto start = std::chrono::steady_clock::now();
  progress_.report = [stage_seen, last_tenth, start](std::string_view stage, double fraction) {
    const int tenth = int(fraction * 10.0);
    if (stage == *stage_seen && tenth == *last_tenth) return;
    *stage_seen = std::string(stage);
    *last_tenth = tenth;
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::fprintf(stderr, "  %7.2f s  %-28s %3d%%\n", seconds, stage_seen->c_str(),
                 int(fraction * 100.0));
  };
}

ConsoleProgress::~ConsoleProgress() {
  std::signal(SIGINT, previous_handler_);
}

}  // namespace lb::app
