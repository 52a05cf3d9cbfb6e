#include "viewer/file_watch.h"

namespace lb {

void FileWatch::watch(const std::string& path) {
  path_ = path;
  seen_ = stamp();
}

bool FileWatch::changed() {
  if (path_.empty()) return false;
  const std::optional<Stamp> now = stamp();
  if (!now || now == seen_) return false;
  seen_ = now;
  return true;
}

std::optional<FileWatch::Stamp> FileWatch::stamp() const {
  std::error_code error;
  Stamp stamp;
  stamp.time = std::filesystem::last_write_time(path_, error);
  if (error) return std::nullopt;
  stamp.size = std::filesystem::file_size(path_, error);
  if (error) return std::nullopt;
  return stamp;
}

}  // namespace lb
