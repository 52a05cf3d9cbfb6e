#pragma once
// Little-endian binary files without padding, read and written whole (the bake directory's
// .bin files, pass-1 shards), and the FNV-1a fingerprint of what a file depends on. Readers
// throw std::runtime_error naming the file and the byte where it went wrong.
//
// A file may end in a checksum (Writer::put_checksum, Reader::check_checksum): the FNV-1a 64
// of every byte before it, so a flipped bit anywhere is refused before anything is parsed.

#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "bake/fnv1a.h"
#include "bake/input_file.h"

namespace lb {

static_assert(std::endian::native == std::endian::little, "bake files are little-endian");

class Writer {
 public:
  template <class T>
  void put(const T& value) {
    const auto* p = reinterpret_cast<const std::byte*>(&value);
    bytes_.insert(bytes_.end(), p, p + sizeof(T));
  }
  template <class T>
  void put_array(const std::vector<T>& values) {
    const auto* p = reinterpret_cast<const std::byte*>(values.data());
    bytes_.insert(bytes_.end(), p, p + values.size() * sizeof(T));
  }
  void put_bytes(const std::string& s) {
    const auto* p = reinterpret_cast<const std::byte*>(s.data());
    bytes_.insert(bytes_.end(), p, p + s.size());
  }
  // Appends the FNV-1a of everything put so far (u64); returns it. Put nothing after it.
  uint64_t put_checksum();
  const std::vector<std::byte>& bytes() const { return bytes_; }

 private:
  std::vector<std::byte> bytes_;
};

class Reader {
 public:
  explicit Reader(std::string path) : path_(std::move(path)) {
    if (const std::string problem = input_file_problem(path_); !problem.empty())
      throw std::runtime_error(path_ + ": cannot open: " + problem);
    std::ifstream in(path_, std::ios::binary);
    if (!in) throw std::runtime_error(path_ + ": cannot open");
    data_.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  template <class T>
  T get() {
    T value;
    take(&value, sizeof(T));
    return value;
  }
  template <class T>
  std::vector<T> get_array(size_t count) {
    if (count > (data_.size() - offset_) / sizeof(T)) fail("truncated");
    std::vector<T> values(count);
    take(values.data(), count * sizeof(T));
    return values;
  }
  std::string get_string(size_t length) {
    if (length > data_.size() - offset_) fail("truncated");
    std::string s(data_.data() + offset_, length);
    offset_ += length;
    return s;
  }
  size_t size() const { return data_.size(); }
  std::span<const std::byte> bytes() const {
    return std::as_bytes(std::span<const char>(data_.data(), data_.size()));
  }
  void expect_magic(const char* magic) {
    if (get_string(8) != magic) fail(std::string("not a ") + magic + " file");
  }
  // Checks the file's last 8 bytes against the FNV-1a of the bytes before them and drops them
  // from what is read; returns the checksum. Call before reading anything.
  uint64_t check_checksum();
  void expect_end() {
    if (offset_ != data_.size()) fail("unexpected trailing data");
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw std::runtime_error(path_ + ": at byte " + std::to_string(offset_) + ": " + what);
  }

 private:
  void take(void* out, size_t size) {
    if (size > data_.size() - offset_) fail("truncated");
    if (size == 0) return;  // `out` may be an empty vector's null data()
    std::memcpy(out, data_.data() + offset_, size);
    offset_ += size;
  }
  std::string path_;
  std::vector<char> data_;
  size_t offset_ = 0;
};


inline uint64_t Writer::put_checksum() {
  const uint64_t checksum = fnv1a(bytes_);
  put(checksum);
  return checksum;
}

inline uint64_t Reader::check_checksum() {
  uint64_t stored = 0;
  const size_t body = data_.size() - sizeof stored;
  if (offset_ == 0 && data_.size() >= sizeof stored)
    std::memcpy(&stored, data_.data() + body, sizeof stored);
  if (offset_ != 0 || data_.size() < sizeof stored || fnv1a(bytes().first(body)) != stored)
    throw std::runtime_error(path_ + ": checksum mismatch: the file is damaged; rebake");
  data_.resize(body);
  return stored;
}

}  // namespace lb
