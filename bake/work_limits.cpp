#include "bake/work_limits.h"

#include <sys/resource.h>

#include <cstdio>
#include <fstream>
#include <stdexcept>

namespace lb {

uint64_t peak_resident_bytes() {
  rusage usage{};
  if (getrusage(RUSAGE_SELF, &usage) != 0) return 0;
  return uint64_t(usage.ru_maxrss) * 1024;  // Linux reports KiB
}

uint64_t available_memory_bytes() {
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  uint64_t kib = 0;
  std::string unit;
  while (meminfo >> key >> kib >> unit)
    if (key == "MemAvailable:") return kib * 1024;
  return 0;
}

std::string format_bytes(double bytes) {
  const char* units[] = {"bytes", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
  int unit = 0;
  while (bytes >= 1024.0 && unit < 6) bytes /= 1024.0, ++unit;
  char text[64];
  std::snprintf(text, sizeof text, unit == 0 ? "%.0f %s" : "%.3g %s", bytes, units[unit]);
  return text;
}

void require_memory(std::string_view what, double bytes) {
  const uint64_t available = available_memory_bytes();
  if (available == 0 || bytes <= double(available)) return;
  throw std::invalid_argument(std::string(what) + " needs about " + format_bytes(bytes) +
                              ", more than the " + format_bytes(double(available)) +
                              " this machine has available");
}

}  // namespace lb
