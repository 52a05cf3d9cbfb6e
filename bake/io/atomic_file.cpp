#include "bake/io/atomic_file.h"

#include <fcntl.h>
#include <stdio.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <system_error>

namespace lb {

namespace fs = std::filesystem;

namespace {

[[noreturn]] void throw_errno(const std::string& path, const std::string& what, int error) {
  throw std::runtime_error(path + ": " + what + ": " + std::strerror(error));
}

std::string parent_directory(const std::string& path) {
  const fs::path parent = fs::path(path).parent_path();
  return parent.empty() ? std::string(".") : parent.string();
}

void require_parent_directory(const std::string& path) {
  std::error_code ec;
  const std::string parent = parent_directory(path);
  if (!fs::is_directory(parent, ec))
    throw std::runtime_error(path + ": cannot write: directory '" + parent + "' does not exist");
}

void sync_directory(const std::string& path) {
  const int fd = ::open(parent_directory(path).c_str(), O_RDONLY | O_DIRECTORY);
  if (fd < 0) return;  // best effort: some filesystems refuse to open directories
  ::fsync(fd);
  ::close(fd);
}

void rename_or_throw(const std::string& from, const std::string& to) {
  if (::rename(from.c_str(), to.c_str()) != 0)
    throw_errno(to, "cannot rename '" + from + "' into place", errno);
}

// Removes a temporary file or directory unless released; keeps error paths free of leftovers.
class TempGuard {
 public:
  explicit TempGuard(std::string path) : path_(std::move(path)) {}
  ~TempGuard() {
    if (path_.empty()) return;
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  void release() { path_.clear(); }

 private:
  std::string path_;
};

}  // namespace

std::string temp_sibling_path(const std::string& path) {
  static std::atomic<unsigned long> counter{0};
  const fs::path target(path);
  const std::string name = ".";
  std::string stem = target.stem().string();
  std::string extension = target.extension().string();
  if (stem.empty()) std::swap(stem, extension);  // dot-files such as ".config"
  const std::string temp_name = name + stem + ".tmp-" + std::to_string(::getpid()) + "-" +
                                std::to_string(counter.fetch_add(1)) + extension;
  return (target.parent_path() / temp_name).string();
}

void write_file_atomic(const std::string& path, std::span<const std::byte> bytes,
                       AtomicWriteOptions options) {
  require_parent_directory(path);
  const std::string temp = temp_sibling_path(path);
  const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) throw_errno(path, "cannot create temporary file '" + temp + "'", errno);
  TempGuard guard(temp);

  const std::byte* data = bytes.data();
  size_t remaining = bytes.size();
  while (remaining > 0) {
    const ssize_t written = ::write(fd, data, remaining);
    if (written < 0) {
      if (errno == EINTR) continue;
      const int error = errno;
      ::close(fd);
      throw_errno(path, "cannot write", error);
    }
    data += written;
    remaining -= size_t(written);
  }
  if (options.sync && ::fsync(fd) != 0) {
    const int error = errno;
    ::close(fd);
    throw_errno(path, "cannot sync", error);
  }
  if (::close(fd) != 0) throw_errno(path, "cannot close", errno);
  rename_or_throw(temp, path);
  guard.release();
  if (options.sync) sync_directory(path);
}

void write_text_atomic(const std::string& path, std::string_view text, AtomicWriteOptions options) {
  write_file_atomic(path, std::as_bytes(std::span(text.data(), text.size())), options);
}

void write_via_temp_file(const std::string& path,
                         const std::function<void(const std::string& temp_path)>& write,
                         AtomicWriteOptions options) {
  require_parent_directory(path);
  const std::string temp = temp_sibling_path(path);
  TempGuard guard(temp);
  write(temp);
  std::error_code ec;
  if (!fs::is_regular_file(temp, ec))
    throw std::runtime_error(path + ": the writer did not produce a file");
  if (options.sync) {
    const int fd = ::open(temp.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd >= 0) {
      ::fsync(fd);
      ::close(fd);
    }
  }
  rename_or_throw(temp, path);
  guard.release();
  if (options.sync) sync_directory(path);
}

// ---------------------------------------------------------------------------------------------
// AtomicDirectory

AtomicDirectory::AtomicDirectory(std::string final_path, AtomicWriteOptions options)
    : final_path_(std::move(final_path)), options_(options) {
  // "bakes/room/" names the same directory as "bakes/room"; drop the trailing separator so the
  // temporary name lands beside it rather than inside it.
  while (final_path_.size() > 1 && final_path_.back() == '/') final_path_.pop_back();
  require_parent_directory(final_path_);
  temp_path_ = temp_sibling_path(final_path_);
  if (::mkdir(temp_path_.c_str(), 0755) != 0)
    throw_errno(final_path_, "cannot create temporary directory '" + temp_path_ + "'", errno);
}

AtomicDirectory::~AtomicDirectory() {
  if (committed_) return;
  std::error_code ec;
  fs::remove_all(temp_path_, ec);
}

std::string AtomicDirectory::file(std::string_view relative) const {
  return (fs::path(temp_path_) / fs::path(relative)).string();
}

void AtomicDirectory::commit() {
  if (committed_) throw std::runtime_error(final_path_ + ": directory already committed");
  if (options_.sync) sync_directory(file("x"));

  std::error_code ec;
  const bool exists = fs::exists(fs::symlink_status(final_path_, ec));
  if (!exists) {
    rename_or_throw(temp_path_, final_path_);
  } else {
#ifdef RENAME_EXCHANGE
    if (::renameat2(AT_FDCWD, temp_path_.c_str(), AT_FDCWD, final_path_.c_str(), RENAME_EXCHANGE) ==
        0) {
      fs::remove_all(temp_path_, ec);  // now holds the previous contents
      committed_ = true;
      if (options_.sync) sync_directory(final_path_);
      return;
    }
#endif
    // No atomic exchange here: move the old directory aside, then the new one in.
    const std::string aside = temp_sibling_path(final_path_);
    rename_or_throw(final_path_, aside);
    try {
      rename_or_throw(temp_path_, final_path_);
    } catch (...) {
      ::rename(aside.c_str(), final_path_.c_str());
      throw;
    }
    fs::remove_all(aside, ec);
  }
  committed_ = true;
  if (options_.sync) sync_directory(final_path_);
}

}  // namespace lb
