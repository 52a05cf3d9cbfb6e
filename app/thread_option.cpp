#include "app/thread_option.h"

#include <tbb/global_control.h>

#include <cstdlib>
#include <string>

namespace lb::app {

namespace {

void limit_threads(int threads) {
  if (threads == 0) return;  // TBB's default: all cores
  // Kept until exit on purpose: destroying it during static destruction races TBB's own.
  static tbb::global_control* limit = nullptr;
  delete limit;
  limit = new tbb::global_control(tbb::global_control::max_allowed_parallelism, size_t(threads));
  ::setenv("LP_NUM_THREADS", std::to_string(threads).c_str(), /*overwrite=*/0);
}

}  // namespace

CLI::Option* add_threads_option(CLI::App& cmd) {
  return cmd
      .add_option_function<int>("--threads", limit_threads,
                                "Worker threads, at most (0: all cores); the result does not "
                                "depend on it")
      ->check(CLI::Range(0, 4096))
      ->default_str("0");
}

}  // namespace lb::app
