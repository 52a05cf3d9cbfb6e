#pragma once
// FNV-1a 64, the content hash every file lightbake writes is recorded by (bake manifests, shard
// and render reports, the export's lightmap files): fast, and enough to tell one run's file
// from another's or from a damaged one (not a defence against forgery).

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <span>
#include <string>

namespace lb {

inline std::string hex_digits(uint64_t value) {
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", (unsigned long long)value);
  return hex;
}

class Fnv1a {
 public:
  void add(const void* data, size_t size) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < size; ++i) hash_ = (hash_ ^ p[i]) * 0x100000001b3ULL;
  }
  template <class T>
  void add(const T& value) {
    add(&value, sizeof(T));
  }
  uint64_t value() const { return hash_; }

 private:
  uint64_t hash_ = 0xcbf29ce484222325ULL;
};

inline uint64_t fnv1a(std::span<const std::byte> bytes) {
  Fnv1a hash;
  hash.add(bytes.data(), bytes.size());
  return hash.value();
}

// FNV-1a of a file's bytes, 16 hex digits (what shard reports and bake manifests record).
inline std::string fnv1a_hex(std::span<const std::byte> bytes) {
  return hex_digits(fnv1a(bytes));
}

// The same, of the file at `path`; throws std::runtime_error naming it if it cannot be read.
inline std::string file_fnv1a_hex(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  Fnv1a hash;
  char buffer[1 << 16];
  while (in.read(buffer, sizeof buffer) || in.gcount() > 0)
    hash.add(buffer, size_t(in.gcount()));
  if (!in.eof()) throw std::runtime_error(path + ": cannot read it back to hash it");
  return hex_digits(hash.value());
}

}  // namespace lb
