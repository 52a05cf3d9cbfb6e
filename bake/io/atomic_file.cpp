#include "bake/io/atomic_file.h"

#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <typeinfo>
#include <optional>
#include <stdexcept>
#include <system_error>
#include <typeinfo>

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

// The parts of a temporary name around "PID-N": ".STEM.tmp-" and the extension.
struct TempNamePattern {
  std::string prefix;
  std::string extension;
};

TempNamePattern temp_name_pattern(const fs::path& target) {
  std::string stem = target.stem().string();
  std::string extension = target.extension().string();
  if (stem.empty()) std::swap(stem, extension);  // dot-files such as ".config"
  return {"." + stem + ".tmp-", extension};
}

bool all_digits(std::string_view text) {
  return !text.empty() && text.find_first_not_of("0123456789") == std::string_view::npos;
}

// The PID in `name` if it is a temporary of the pattern ("PREFIX<PID>-<N>EXTENSION").
std::optional<pid_t> temporary_owner(std::string_view name, const TempNamePattern& pattern) {
  if (!name.starts_with(pattern.prefix) || !name.ends_with(pattern.extension)) return {};
  name.remove_prefix(pattern.prefix.size());
  name.remove_suffix(pattern.extension.size());
  const size_t dash = name.find('-');
  if (dash == std::string_view::npos || !all_digits(name.substr(0, dash)) ||
      !all_digits(name.substr(dash + 1)) || dash > 9)
    return {};
  return pid_t(std::stol(std::string(name.substr(0, dash))));
}

bool process_is_gone(pid_t pid) {
  return pid != ::getpid() && ::kill(pid, 0) != 0 && errno == ESRCH;
}

}  // namespace

std::string temp_sibling_path(const std::string& path) {
  static std::atomic<unsigned long> counter{0};
  const fs::path target(path);
  const TempNamePattern pattern = temp_name_pattern(target);
  const std::string temp_name = pattern.prefix + std::to_string(::getpid()) + "-" +
                                std::to_string(counter.fetch_add(1)) + pattern.extension;
  return (target.parent_path() / temp_name).string();
}

int sweep_stale_temporaries(const std::string& path) {
  const fs::path target(path);
  const TempNamePattern pattern = temp_name_pattern(target);
  std::error_code ec;
  // Without the final path, a stale directory may be the only complete copy (a rename-aside
  // replacement killed between its two renames): keep those for the user to recover.
  const bool final_exists = fs::exists(fs::symlink_status(target, ec));
  int swept = 0;
  for (const fs::directory_entry& entry : fs::directory_iterator(
           parent_directory(path), fs::directory_options::skip_permission_denied, ec)) {
    const std::optional<pid_t> owner = temporary_owner(entry.path().filename().string(), pattern);
    if (!owner || !process_is_gone(*owner)) continue;
    if (!final_exists && entry.is_directory(ec)) continue;
    if (fs::remove_all(entry.path(), ec) > 0 && !ec) ++swept;
  }
  return swept;
}

namespace {

// Writes `bytes` to the new file `temp` (errors name `path`, the file it stands for).
void write_new_file(const std::string& path, const std::string& temp,
                    std::span<const std::byte> bytes, AtomicWriteOptions options) {
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
  guard.release();
}

void sync_file(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd >= 0) {
    ::fsync(fd);
    ::close(fd);
  }
}

// Runs a writer that opens `temp` itself; throws naming `path` if it made no file.
void write_with(const std::string& path, const std::string& temp,
                const std::function<void(const std::string& temp_path)>& write,
                AtomicWriteOptions options) {
  try {
    write(temp);
  } catch (...) {
    rethrow_naming(temp, path);
  }
  std::error_code ec;
  if (!fs::is_regular_file(temp, ec))
    throw std::runtime_error(path + ": the writer did not produce a file");
  if (options.sync) sync_file(temp);
}

}  // namespace

std::optional<FileIdentity> file_identity(const std::string& path) {
  struct stat status{};
  if (::stat(path.c_str(), &status) != 0) return std::nullopt;
  return FileIdentity{uint64_t(status.st_dev), uint64_t(status.st_ino)};
}

void remove_if_same_file(const std::string& path, FileIdentity identity) {
  const std::optional<FileIdentity> now = file_identity(path);
  if (now && now->device == identity.device && now->inode == identity.inode)
    ::unlink(path.c_str());
}

void rethrow_naming(std::span<const std::pair<std::string, std::string>> temp_final) {
  try {
    throw;
  } catch (const std::runtime_error& e) {
    if (typeid(e) != typeid(std::runtime_error)) throw;
    std::string message = e.what();
    for (const auto& [temp, final_path] : temp_final) {
      if (temp.empty()) continue;
      for (size_t at = message.find(temp); at != std::string::npos;
           at = message.find(temp, at + final_path.size()))
        message.replace(at, temp.size(), final_path);
    }
    throw std::runtime_error(message);
  }
}

void rethrow_naming(const std::string& temp, const std::string& final_path) {
  const std::pair<std::string, std::string> pair(temp, final_path);
  rethrow_naming(std::span(&pair, 1));
}

void write_file_atomic(const std::string& path, std::span<const std::byte> bytes,
                       AtomicWriteOptions options) {
  require_parent_directory(path);
  sweep_stale_temporaries(path);
  const std::string temp = temp_sibling_path(path);
  write_new_file(path, temp, bytes, options);
  TempGuard guard(temp);
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
  sweep_stale_temporaries(path);
  const std::string temp = temp_sibling_path(path);
  TempGuard guard(temp);
  write_with(path, temp, write, options);
  rename_or_throw(temp, path);
  guard.release();
  if (options.sync) sync_directory(path);
}

void write_pair_atomic(const std::string& first_path,
                       const std::function<void(const std::string& temp_path)>& write_first,
                       const std::string& second_path,
                       const std::function<std::string(const std::string& first_temp)>& second,
                       AtomicWriteOptions options) {
  require_parent_directory(first_path);
  require_parent_directory(second_path);
  sweep_stale_temporaries(first_path);
  sweep_stale_temporaries(second_path);
  const std::string first_temp = temp_sibling_path(first_path);
  const std::string second_temp = temp_sibling_path(second_path);
  TempGuard first_guard(first_temp);
  write_with(first_path, first_temp, write_first, options);
  const std::string text = second(first_temp);
  write_new_file(second_path, second_temp, std::as_bytes(std::span(text.data(), text.size())),
                 options);
  TempGuard second_guard(second_temp);
  // Both are whole before either is published; the first is known by its inode, so a failed
  // second rename removes only the file this call put in place, never a concurrent writer's.
  const std::optional<FileIdentity> first = file_identity(first_temp);
  if (!first) throw_errno(first_path, "cannot stat", errno);
  rename_or_throw(first_temp, first_path);
  first_guard.release();
  try {
    rename_or_throw(second_temp, second_path);
  } catch (...) {
    remove_if_same_file(first_path, *first);
    throw;
  }
  second_guard.release();
  if (options.sync) {
    sync_directory(first_path);
    sync_directory(second_path);
  }
}

// ---------------------------------------------------------------------------------------------
// AtomicDirectory

namespace {

// `from` recreated at `to` out of hard links (directories made anew, symbolic links copied), so
// `to` holds the same files without a byte copied. Throws naming `from` for what cannot be linked.
void link_tree(const fs::path& from, const fs::path& to) {
  std::error_code ec;
  const fs::file_status status = fs::symlink_status(from, ec);
  if (fs::is_symlink(status)) {
    fs::copy_symlink(from, to, ec);
  } else if (fs::is_regular_file(status)) {
    fs::create_hard_link(from, to, ec);
  } else if (fs::is_directory(status)) {
    if (fs::create_directory(to, ec); !ec)
      for (const fs::directory_entry& entry : fs::directory_iterator(from, ec))
        link_tree(entry.path(), to / entry.path().filename());
  } else {
    throw std::runtime_error(from.string() +
                             ": cannot keep this kind of file while replacing its folder; move "
                             "it out and try again");
  }
  if (ec)
    throw std::runtime_error(from.string() +
                             ": cannot keep it while replacing its folder: " + ec.message());
}

bool is_inside(const fs::path& path, const fs::path& folder) {
  const auto [end, _] = std::mismatch(folder.begin(), folder.end(), path.begin(), path.end());
  return end == folder.end();
}

}  // namespace

AtomicDirectory::AtomicDirectory(std::string final_path, std::vector<std::string> superseded,
                                 AtomicWriteOptions options)
    : superseded_(std::move(superseded)), options_(options) {
  // "bakes/room/" names the same directory as "bakes/room"; drop the trailing separator so the
  // temporary name lands beside it rather than inside it. "." and links resolve to the folder
  // they name, so the temporary is its sibling and a link is followed, not replaced.
  while (final_path.size() > 1 && final_path.back() == '/') final_path.pop_back();
  require_parent_directory(final_path);
  std::error_code ec;
  const fs::path resolved = fs::weakly_canonical(fs::absolute(final_path), ec);
  final_path_ = ec ? final_path : resolved.string();
  if (fs::exists(fs::symlink_status(final_path_, ec))) {
    if (!fs::is_directory(final_path_, ec))
      throw std::runtime_error(final_path + ": exists and is not a folder; choose another name");
    if (is_inside(fs::current_path(ec), final_path_))
      throw std::runtime_error(final_path +
                               ": is the current folder or holds it; write to another folder");
  }
  sweep_stale_temporaries(final_path_);
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

bool AtomicDirectory::is_superseded(std::string_view name) const {
  return std::find(superseded_.begin(), superseded_.end(), name) != superseded_.end();
}

void AtomicDirectory::carry_over_old_entries() const {
  for (const fs::directory_entry& entry : fs::directory_iterator(final_path_)) {
    const std::string name = entry.path().filename().string();
    std::error_code ec;
    if (is_superseded(name) || fs::exists(fs::symlink_status(file(name), ec))) continue;
    link_tree(entry.path(), file(name));
  }
}

void AtomicDirectory::commit() {
  if (committed_) throw std::runtime_error(final_path_ + ": directory already committed");

  std::error_code ec;
  const bool exists = fs::exists(fs::symlink_status(final_path_, ec));
  if (exists) {
    if (!fs::is_directory(fs::symlink_status(final_path_, ec)))
      throw std::runtime_error(final_path_ + ": exists and is not a folder; nothing written");
    carry_over_old_entries();
  }
  if (options_.sync) sync_directory(file("x"));
  if (!exists) {
    rename_or_throw(temp_path_, final_path_);
    committed_ = true;
    if (options_.sync) sync_directory(final_path_);
    return;
  }

  // After the swap temp_path_ names the old directory. Anything that appeared in it since the
  // carry-over moves across too, so removing it loses nothing.
  std::string old_path = temp_path_;
#ifdef RENAME_EXCHANGE
  const bool exchanged = ::renameat2(AT_FDCWD, temp_path_.c_str(), AT_FDCWD, final_path_.c_str(),
                                     RENAME_EXCHANGE) == 0;
#else
  const bool exchanged = false;
#endif
  if (!exchanged) {
    // No atomic exchange here: move the old directory aside, then the new one in.
    old_path = temp_sibling_path(final_path_);
    rename_or_throw(final_path_, old_path);
    try {
      rename_or_throw(temp_path_, final_path_);
    } catch (...) {
      ::rename(old_path.c_str(), final_path_.c_str());
      throw;
    }
  }
  committed_ = true;
  for (const fs::directory_entry& entry : fs::directory_iterator(old_path, ec)) {
    const fs::path moved = fs::path(final_path_) / entry.path().filename();
    if (!is_superseded(entry.path().filename().string()) &&
        !fs::exists(fs::symlink_status(moved, ec)))
      fs::rename(entry.path(), moved, ec);
  }
  fs::remove_all(old_path, ec);
  if (options_.sync) sync_directory(final_path_);
}

}  // namespace lb
