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
  struct State {
    std::string stage;
    int tenth = -1;
    double stage_start = 0.0;  // seconds since start
    double printed = 0.0;      // when the last line went out
  };
  auto state = std::make_shared<State>();
  const auto start = std::chrono::steady_clock::now();
  progress_.report = [state, start](std::string_view stage, double fraction) {
    const int tenth = int(fraction * 10.0);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    // A line per stage, per tenth, and every 10 s between them in long stages.
    if (stage == state->stage && tenth == state->tenth && seconds - state->printed < 10.0) return;
    state->printed = seconds;
    if (stage != state->stage) state->stage_start = seconds;
    state->stage = std::string(stage);
    state->tenth = tenth;
    // Time left in this stage, assuming the rest goes as fast as the part done.
    const double spent = seconds - state->stage_start;
    char left[32] = "";
    if (fraction > 0.0 && fraction < 1.0 && spent > 0.5)
      std::snprintf(left, sizeof left, "  ~%.0f s left", spent * (1.0 - fraction) / fraction);
    std::fprintf(stderr, "  %7.2f s  %-28s %3d%%%s\n", seconds, state->stage.c_str(),
                 int(fraction * 100.0), left);
  };
}

ConsoleProgress::~ConsoleProgress() {
  std::signal(SIGINT, previous_handler_);
}

}  // namespace lb::app
