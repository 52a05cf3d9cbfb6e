#include "app/output_path.h"

#include <filesystem>
#include <stdexcept>
#include <system_error>

namespace lb::app {

void prepare_output_path(const std::string& path) {
  const std::filesystem::path parent = std::filesystem::absolute(path).parent_path();
  std::error_code error;
  std::filesystem::create_directories(parent, error);
  if (error || !std::filesystem::is_directory(parent))
    throw std::runtime_error(path + ": cannot create folder '" + parent.string() + "'" +
                             (error ? ": " + error.message() : ""));
}

}  // namespace lb::app
