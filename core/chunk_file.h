// A versioned container of named binary chunks (checkpoints), with a checksum and bounds-checked reads.
#pragma once

#include <bit>
#include <cstdint>
#include <cstring>
#include <map>
#include <string>
#include <type_traits>
#include <vector>

#include "core/errors.h"

namespace cellform::core {

// checkpoints and the binary files written through ByteWriter copy values in host order, as little-endian
static_assert(std::endian::native == std::endian::little, "cellform's binary files need a little-endian host");

/// Appends plain values and arrays to a byte string (little-endian machine layout).
class ByteWriter {
 public:
  template <class T>
  void put(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    bytes_.append(reinterpret_cast<const char*>(&v), sizeof(T));
  }
  template <class T>
  void put_vector(const std::vector<T>& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    put<std::uint64_t>(v.size());
    bytes_.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
  }
  void put_string(const std::string& s) {
    put<std::uint64_t>(s.size());
    bytes_.append(s);
  }
  std::string take() { return std::move(bytes_); }

 private:
  std::string bytes_;
};

/// Reads what ByteWriter wrote; throws FileError naming `what` if the data runs short.
class ByteReader {
 public:
  ByteReader(const std::string& bytes, std::string what) : bytes_(bytes), what_(std::move(what)) {}
  template <class T>
  T get() {
    static_assert(std::is_trivially_copyable_v<T>);
    need(sizeof(T));
    T v;
    std::memcpy(&v, bytes_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  template <class T>
  std::vector<T> get_vector() {
    const auto n = get<std::uint64_t>();
    if (n > (bytes_.size() - pos_) / sizeof(T)) fail();
    std::vector<T> v(n);
    if (n > 0) std::memcpy(v.data(), bytes_.data() + pos_, n * sizeof(T));  // an empty vector's data() may be null
    pos_ += n * sizeof(T);
    return v;
  }
  std::string get_string() {
    const auto n = get<std::uint64_t>();
    need(n);
    std::string s = bytes_.substr(pos_, n);
    pos_ += n;
    return s;
  }
  bool done() const { return pos_ == bytes_.size(); }

 private:
  void need(std::size_t n) const {
    if (n > bytes_.size() - pos_) fail();
  }
  [[noreturn]] void fail() const { throw FileError(what_ + " is corrupt (data ends early)"); }
  const std::string& bytes_;
  std::string what_;
  std::size_t pos_ = 0;
};

/// 64-bit FNV-1a hash (checksums, script hashes).
std::uint64_t fnv1a64(const void* data, std::size_t n, std::uint64_t h = 0xcbf29ce484222325ull);

/// Hex string of a 64-bit value, 16 digits.
std::string hex64(std::uint64_t v);

/// Serialises chunks: magic "CELLFORM", a 4-character kind, the format version, then
/// (tag, length, bytes) records, then an FNV-1a checksum of everything before it.
std::string write_chunk_file(const std::string& kind, std::uint32_t version,
                             const std::map<std::string, std::string>& chunks);

/// A parsed chunk file.
struct ChunkFile {
  std::uint32_t version = 0;
  std::map<std::string, std::string> chunks;

  /// The chunk `tag`; FileError naming `what` if it is absent.
  const std::string& at(const std::string& tag, const std::string& what) const;
};

/// Parses `bytes` as a chunk file of `kind`; FileError naming `what` for a foreign file, a wrong kind,
/// a version newer than `max_version`, truncation or a checksum mismatch.
ChunkFile read_chunk_file(const std::string& bytes, const std::string& kind, std::uint32_t max_version,
                          const std::string& what);

}  // namespace cellform::core
