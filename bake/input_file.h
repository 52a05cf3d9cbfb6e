#pragma once
// Whether a path may be opened as an input file, and its extension. Header-only: readers in
// every module (bake files, reference films, the command line) ask them.

#include <cctype>
#include <filesystem>
#include <string>

namespace lb {

// Why `path` cannot be read as an input file (scene, include, mesh, texture, sky image, bake
// file), or "" when it can: "does not exist", "is a directory", "is not a regular file (a FIFO
// or a device)". Asked before opening: opening a FIFO blocks until a writer comes, and a
// device (/dev/zero) would be read forever.
inline std::string input_file_problem(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code error;
  const fs::file_status status = fs::status(path, error);  // follows links, as open() does
  if (!fs::exists(status)) return "does not exist";
  if (fs::is_directory(status)) return "is a directory";
  if (!fs::is_regular_file(status)) return "is not a regular file (a FIFO or a device)";
  return {};
}

// The extension of `path` in lower case, with its dot (".exr"; "" without one): what the
// readers and writers choose a format by.
inline std::string lowercase_extension(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  for (char& c : extension) c = char(std::tolower(static_cast<unsigned char>(c)));
  return extension;
}

}  // namespace lb
