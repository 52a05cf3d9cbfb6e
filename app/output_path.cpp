#include "app/output_path.h"

#include <fcntl.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <system_error>

#include "bake/export/gltf_export.h"
#include "bake/io/atomic_file.h"
#include "bake/io/image_io.h"
#include "bake/shards/shard_file.h"
#include "bake/work_limits.h"

namespace lb::app {

namespace fs = std::filesystem;

void prepare_output_path(const std::string& path) {
  // A bake's folder may exist already (a rebake): its own file system then.
  const fs::path parent =
      fs::is_directory(path) ? fs::absolute(path) : fs::absolute(path).parent_path();
  std::error_code error;
  fs::create_directories(parent, error);
  if (error || !fs::is_directory(parent))
    throw std::runtime_error(path + ": cannot create folder '" + parent.string() + "'" +
                             (error ? ": " + error.message() : ""));
  // A folder that takes no new file (read-only, no permission, a read-only file system) is
  // found now, by making and removing a temporary beside the output, not after the work.
  const std::string probe = temp_sibling_path(fs::absolute(path).string());
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
  if (fd < 0)
    throw std::runtime_error(path + ": cannot write into folder '" + parent.string() +
                             "': " + std::strerror(errno));
  ::close(fd);
  ::unlink(probe.c_str());
}

void require_free_space(const std::string& path, double bytes) {
  // A bake's folder may exist already (a rebake): its own file system then.
  const fs::path parent =
      fs::is_directory(path) ? fs::absolute(path) : fs::absolute(path).parent_path();
  struct statvfs disk{};
  if (::statvfs(parent.c_str(), &disk) != 0) return;  // unknown: the write will say
  const double free_bytes = double(disk.f_bavail) * double(disk.f_frsize);
  if (free_bytes >= bytes) return;
  throw std::runtime_error(path + ": the folder '" + parent.string() + "' has " +
                           format_bytes(free_bytes) + " free, the output needs about " +
                           format_bytes(bytes) + "; free some space or choose another folder");
}

double image_output_bytes(int width, int height) {
  return double(width) * double(height) * 16.0 + 65536.0;
}

bool written_by_lightbake(const std::string& path) {
  if (fs::path(path).extension() == ".json") {
    std::ifstream in(path);
    const nlohmann::json report = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
    return report.is_object() && report.value("generator", nlohmann::json()) == "lightbake";
  }
  const fs::path extension = fs::path(path).extension();
  if (extension == ".glb" || extension == ".gltf") return is_lightbake_gltf(path);
  return shards::is_shard_file(path) || is_lightbake_image(path);
}

void prepare_output_file(const std::string& path, bool force) {
  prepare_output_path(path);
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (!fs::exists(status)) return;
  if (!fs::is_regular_file(status))
    throw std::runtime_error(path + ": exists and is not a file; choose another name");
  if (!force && !written_by_lightbake(path))
    throw std::runtime_error(path +
                             ": exists and was not written by lightbake; choose another name or "
                             "pass --force to replace it");
}

}  // namespace lb::app
