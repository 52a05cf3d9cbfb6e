#pragma once
// Tells when a file changed on disk, by its modification time and size, for the viewer's
// reload-on-save (polled twice a second: a stat per poll, no inotify).

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

namespace lb {

class FileWatch {
 public:
  // Watches `path` from now on: its present state is the one changes are measured from.
  void watch(const std::string& path);
  // True once per change since watch() or the last true. A missing file is no change (an
  // editor may delete and rewrite it); its return with a new time or size is.
  bool changed();
  const std::string& path() const { return path_; }

 private:
  struct Stamp {
    std::filesystem::file_time_type time;
    uintmax_t size = 0;
    bool operator==(const Stamp&) const = default;
  };
  std::optional<Stamp> stamp() const;
  std::string path_;
  std::optional<Stamp> seen_;
};

}  // namespace lb
