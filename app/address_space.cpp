#include "app/address_space.h"

#include <sys/resource.h>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <thread>

#include "bake/scene.h"
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

// The room's triangles: its scene-dependent part is in kNeeds already.
constexpr uint64_t kMeasuredTriangles = 4041;

// What the command being run was found to need when its options were parsed.
struct CommandNeed {
  std::string name;
  int threads = 0;
  double bytes = 0;  // 0: no limit or a command without a need
  bool per_thread = false;
};
CommandNeed& command_need() {
  static CommandNeed need;
  return need;
}

double address_space_limit() {
  rlimit limit{};
  if (::getrlimit(RLIMIT_AS, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY) return 0;
  return double(limit.rlim_cur);
}

[[noreturn]] void refuse(const CommandNeed& need, double limit, double bytes,
                         const std::string& scene) {
  throw std::runtime_error(
      need.name + ": the address-space limit (ulimit -v) of " + format_bytes(limit) +
      " is below the " + format_bytes(bytes) + " that " + need.name + " maps with " +
      std::to_string(need.threads) + (need.threads == 1 ? " thread" : " threads") + scene +
      " (its libraries, stacks and heaps); raise the limit" +
      (need.per_thread && need.threads > 1 ? " or lower --threads" : ""));
}

void check(const CLI::App& cmd) {
  const double limit = address_space_limit();
  if (limit == 0) return;
  const std::string name = cmd.get_name();
  const auto need = std::find_if(std::begin(kNeeds), std::end(kNeeds),
                                 [&](const AddressSpaceNeed& n) { return name == n.command; });
  if (need == std::end(kNeeds)) return;
  CommandNeed& found = command_need();
  found.name = name;
  found.threads = thread_count(cmd);
  found.per_thread = need->per_thread_mib > 0;
  found.bytes = kMargin * kMiB *
                (need->at_two_threads_mib + need->per_thread_mib * double(found.threads - 2));
  if (limit < found.bytes) refuse(found, limit, found.bytes, "");
}

}  // namespace

void add_address_space_check(CLI::App& cmd) {
  cmd.parse_complete_callback([&cmd] { check(cmd); });
}

void require_address_space_for(const Scene& scene) {
  const CommandNeed& need = command_need();
  const double limit = address_space_limit();
  if (limit == 0 || need.bytes == 0) return;
  // Each triangle more than the room's maps what a bake holds for it (mesh, BVH, charts,
  // refined triangles): the bake's own per-triangle estimate, the most of any command's.
  const uint64_t triangles = triangle_count(scene);
  const double more = estimate_bake_bytes(triangles) - estimate_bake_bytes(kMeasuredTriangles);
  const double bytes = need.bytes + kMargin * std::max(0.0, more);
  if (limit < bytes)
    refuse(need, limit, bytes,
           " for the " + std::to_string(triangles) + " triangles of " + scene.source_path);
}

std::string out_of_memory_text(const std::string& doing) {
  if (const double limit = address_space_limit(); limit > 0)
    return "ran out of memory" + doing + " under the address-space limit (ulimit -v) of " +
           format_bytes(limit) + "; raise the limit";
  const uint64_t available = available_memory_bytes();
  return "ran out of memory" + doing +
         (available > 0 ? " (" + format_bytes(double(available)) + " available)" : std::string());
}

}  // namespace lb::app
