#include "bake/work_limits.h"

#include <sys/resource.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <string>

namespace lb {

uint64_t peak_resident_bytes() {
  rusage usage{};
  if (getrusage(RUSAGE_SELF, &usage) != 0) return 0;
  return uint64_t(usage.ru_maxrss) * 1024;  // Linux reports KiB
}

namespace {

uint64_t meminfo_available() {
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  uint64_t kib = 0;
  std::string unit;
  while (meminfo >> key >> kib >> unit)
    if (key == "MemAvailable:") return kib * 1024;
  return 0;
}

// cgroup v2 ("0::/path" in /proc/self/cgroup): memory.max less memory.current; 0 if there is
// no limit ("max") or no cgroup v2.
uint64_t cgroup_available() {
  std::ifstream self("/proc/self/cgroup");
  std::string line, path;
  while (std::getline(self, line))
    if (line.rfind("0::", 0) == 0) path = "/sys/fs/cgroup" + line.substr(3);
  if (path.empty()) return 0;
  std::ifstream max_file(path + "/memory.max"), current_file(path + "/memory.current");
  std::string max_text;
  uint64_t current = 0;
  if (!(max_file >> max_text) || max_text == "max" || !(current_file >> current)) return 0;
  const uint64_t max = std::strtoull(max_text.c_str(), nullptr, 10);
  return max > current ? max - current : 1;
}

uint64_t least_known(uint64_t a, uint64_t b) {
  return a == 0 ? b : b == 0 ? a : std::min(a, b);
}

}  // namespace

uint64_t parse_memory_size(std::string_view text) {
  uint64_t value = 0;
  size_t digits = 0;
  while (digits < text.size() && text[digits] >= '0' && text[digits] <= '9') {
    if (value > (uint64_t(1) << 50)) throw std::invalid_argument("too large");
    value = value * 10 + uint64_t(text[digits++] - '0');
  }
  const std::string_view suffix = text.substr(digits);
  int shift = -1;
  if (suffix.empty()) shift = 0;
  if (suffix == "K" || suffix == "KiB") shift = 10;
  if (suffix == "M" || suffix == "MiB") shift = 20;
  if (suffix == "G" || suffix == "GiB") shift = 30;
  if (digits == 0 || shift < 0 || value == 0)
    throw std::invalid_argument(
        "expected a size in bytes with an optional K, M or G suffix, got '" + std::string(text) +
        "'");
  return value << shift;
}

uint64_t available_memory_bytes() {
  uint64_t available = least_known(meminfo_available(), cgroup_available());
  if (const char* cap = std::getenv("LIGHTBAKE_MAX_MEMORY"); cap && *cap) {
    try {
      available = least_known(available, parse_memory_size(cap));
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string("LIGHTBAKE_MAX_MEMORY: ") + e.what());
    }
  }
  return available;
}

std::string format_bytes(double bytes) {
  const char* units[] = {"bytes", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
  int unit = 0;
  while (bytes >= 1024.0 && unit < 6) bytes /= 1024.0, ++unit;
  char text[64];
  // Three significant digits, but never an exponent ("1020 MiB", not "1.02e+03 MiB").
  std::snprintf(text, sizeof text, unit == 0 || bytes >= 100.0 ? "%.0f %s" : "%.3g %s", bytes,
                units[unit]);
  return text;
}

double estimate_bake_bytes(uint64_t triangles) {
  // 375 MiB: the small level peaked at 75 MiB and the 92k level at 241 MiB without OpenImageIO
  // in the process; writing the maps loads it (bake/io/image_plugin.h), which adds 113 MiB of
  // resident libraries (the Cornell box at draft: 70 -> 183 MiB).
  constexpr double kFixedBytes = 375.0 * (1 << 20);
  constexpr double kBytesPerTriangle = 400.0;
  return kFixedBytes + kBytesPerTriangle * double(triangles);
}

void require_memory(std::string_view what, double bytes) {
  const uint64_t available = available_memory_bytes();
  if (available == 0 || bytes <= double(available)) return;
  throw std::invalid_argument(std::string(what) + " needs about " + format_bytes(bytes) +
                              ", more than the " + format_bytes(double(available)) +
                              " available to it (the least of free memory, the cgroup's limit and "
                              "LIGHTBAKE_MAX_MEMORY)");
}

void release_freed_memory() {
#ifdef __GLIBC__
  malloc_trim(0);
#endif
}

}  // namespace lb
