#pragma once
// Whole-file and whole-directory writes that never leave a half-written result behind: the
// data goes to a temporary name in the destination's own directory (so the final rename stays
// on one filesystem and is atomic), and only a complete file or directory is renamed into
// place. Every error throws std::runtime_error whose message starts with the path involved.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace lb {

struct AtomicWriteOptions {
  bool sync = false;  // fsync the data (and the directory) before and after the rename
};

// Writes `bytes` to `path` as one atomic replacement. The parent directory must exist.
void write_file_atomic(const std::string& path, std::span<const std::byte> bytes,
                       AtomicWriteOptions options = {});
// Same for text (JSON, TOML, manifests): the string's bytes are written unchanged.
void write_text_atomic(const std::string& path, std::string_view text,
                       AtomicWriteOptions options = {});

// For writers that insist on opening a file name themselves (a library given only a path):
// calls `write(temp_path)`, where temp_path is a fresh name in path's directory that keeps
// path's extension, then renames temp_path to `path`. If `write` throws, the temporary file is
// removed and the exception propagates unchanged; if it returns without creating the file, a
// runtime_error is thrown.
void write_via_temp_file(const std::string& path,
                         const std::function<void(const std::string& temp_path)>& write,
                         AtomicWriteOptions options = {});

// Two files that belong together (an image and its report) appear together or not at all:
// `write_first(temp)` writes the first under a temporary name beside `first_path`, `second`
// returns the second's text given that temporary (to record the first's hash, say), then the
// first and the second are renamed into place in that order. If any step fails, the
// temporaries and the first file this call renamed into place are removed, and the exception
// propagates. Between the two renames a reader sees the new first with the old second: the
// second should record what tells them apart (the first's content hash).
void write_pair_atomic(const std::string& first_path,
                       const std::function<void(const std::string& temp_path)>& write_first,
                       const std::string& second_path,
                       const std::function<std::string(const std::string& first_temp)>& second,
                       AtomicWriteOptions options = {});

// A file told apart from any other by device and inode: a writer that renamed it into place
// can undo that later without removing a file a concurrent writer has put there since.
struct FileIdentity {
  uint64_t device = 0;
  uint64_t inode = 0;
};
// The identity of the file at `path`; nullopt (errno set) when it cannot be stat'ed.
std::optional<FileIdentity> file_identity(const std::string& path);
// Removes `path` only while it is still the file `identity` names.
void remove_if_same_file(const std::string& path, FileIdentity identity);

// Call in a catch block: rethrows the exception in flight, but a plain std::runtime_error's
// message with every `temp` replaced by `final_path`, so a write error names the file the user
// asked for ("out.png: cannot write: No space left on device"), not its temporary.
[[noreturn]] void rethrow_naming(const std::string& temp, const std::string& final_path);
// The same for several (temporary, final) pairs.
[[noreturn]] void rethrow_naming(std::span<const std::pair<std::string, std::string>> temp_final);

// A unique temporary sibling of `path`: "DIR/.NAME.tmp-PID-N.EXT". Not created.
std::string temp_sibling_path(const std::string& path);

// Removes the temporaries of `path` (names as temp_sibling_path makes them) that were left by
// processes no longer running (killed mid-write). Only names of exactly that form whose PID is
// dead are touched; a live or unknown process's temporaries stay. Returns how many went. The
// writers below call it, so a killed run is cleaned up by the next one.
int sweep_stale_temporaries(const std::string& path);

// Builds a directory under a temporary name and renames it into place on commit():
//
//   AtomicDirectory out("bakes/room");          // creates bakes/.room.tmp-PID-N/
//   write_text_atomic(out.file("manifest.json"), json);
//   write_exr(out.file("lightmap.exr"), image);
//   out.commit();                                // bakes/room now holds exactly those files
//
// commit() replaces an existing directory at the final path: on Linux by an atomic exchange
// (renameat2 RENAME_EXCHANGE) and removal of the old one, elsewhere by rename-aside. It never
// loses what the old directory held that the writer does not own: every old entry the new
// directory does not have, and whose name is not in `superseded`, is carried into the new
// directory first, as hard links (nothing is copied, and a kill at any moment leaves either
// the old directory or the new one, each complete). An existing path that is not a directory
// is refused. If the object is destroyed without commit() (an exception, a cancelled bake),
// the temporary directory and everything in it are removed. The parent directory must exist;
// the final path is resolved (symbolic links, "." and "..") before anything is written.
class AtomicDirectory {
 public:
  // `superseded`: names of old entries the writer owns and replaces (files of an earlier
  // format, say); they go with the old directory even when the new one has no such entry.
  explicit AtomicDirectory(std::string final_path, std::vector<std::string> superseded = {},
                           AtomicWriteOptions options = {});
  ~AtomicDirectory();
  AtomicDirectory(const AtomicDirectory&) = delete;
  AtomicDirectory& operator=(const AtomicDirectory&) = delete;

  const std::string& final_path() const { return final_path_; }
  const std::string& temp_path() const { return temp_path_; }
  // The path of `relative` inside the temporary directory (write files there before commit).
  std::string file(std::string_view relative) const;
  void commit();
  bool committed() const { return committed_; }

 private:
  bool is_superseded(std::string_view name) const;
  void carry_over_old_entries() const;

  std::string final_path_;
  std::string temp_path_;
  std::vector<std::string> superseded_;
  AtomicWriteOptions options_;
  bool committed_ = false;
};

}  // namespace lb
