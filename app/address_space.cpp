#include "app/address_space.h"

#include <sys/resource.h>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <thread>

#include "bake/work_limits.h"

namespace lb::app {

namespace {

constexpr double kMiB = 1024.0 * 1024.0;

struct AddressSpaceNeed {
  const char* command;
  double at_two_threads_mib;  // the least limit that ran the bundled room, measured, 2 threads
  double per_thread_mib;  // each thread more (or fewer) than two
};

// Measured on the bundled room (scenes/room.toml, draft bake, 80x60 images) by bisecting
// `ulimit -v` to 25 MiB, the highest of a few runs (where the failure falls varies by ~70 MiB
// with thread timing). Threads map stacks and malloc arenas; llvmpipe's also LLVM's code.
constexpr AddressSpaceNeed kNeeds[] = {
    {"info", 470, 0},      {"compare", 710, 0},     {"merge", 710, 0},
    {"bake", 730, 70},     {"render", 930, 70},     {"reference", 930, 70},
    {"export", 990, 70},   {"snapshot", 1380, 200}, {"view", 1380, 200},
};
constexpr double kMargin = 1.1;  // bigger scenes map more; the bake checks its own estimate too

int thread_count(const CLI::App& cmd) {
  int threads = 0;
  if (const CLI::Option* option = cmd.get_option_no_throw("--threads"); option && option->count())
    threads = option->as<int>();
  return threads > 0 ? threads : int(std::max(1u, std::thread::hardware_concurrency()));
}

void check(const CLI::App& cmd) {
  rlimit limit{};
  if (::getrlimit(RLIMIT_AS, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY) return;
  const std::string name = cmd.get_name();
  const auto need = std::find_if(std::begin(kNeeds), std::end(kNeeds),
                                 [&](const AddressSpaceNeed& n) { return name == n.command; });
  if (need == std::end(kNeeds)) return;
  const int threads = thread_count(cmd);
  const double bytes =
      kMargin * kMiB *
      (need->at_two_threads_mib + need->per_thread_mib * double(threads - 2));
  if (double(limit.rlim_cur) >= bytes) return;
  throw std::runtime_error(
      name + ": the address-space limit (ulimit -v) of " + format_bytes(double(limit.rlim_cur)) +
      " is below the " + format_bytes(bytes) + " that " + name + " maps with " +
      std::to_string(threads) + (threads == 1 ? " thread" : " threads") +
      " (its libraries, stacks and heaps); raise the limit" +
      (need->per_thread_mib > 0 && threads > 1 ? " or lower --threads" : ""));
}

}  // namespace

void add_address_space_check(CLI::App& cmd) {
  cmd.parse_complete_callback([&cmd] { check(cmd); });
}

}  // namespace lb::app
