// Chunk container with checksum.
#include "core/chunk_file.h"

#include <cstdio>

namespace cellform::core {

namespace {
constexpr char kMagic[8] = {'C', 'E', 'L', 'L', 'F', 'O', 'R', 'M'};
}

std::uint64_t fnv1a64(const void* data, std::size_t n, std::uint64_t h) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < n; ++i) {
    h ^= p[i];
    h *= 0x100000001b3ull;
  }
  return h;
}

std::string hex64(std::uint64_t v) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(v));
  return buf;
}

std::string write_chunk_file(const std::string& kind, std::uint32_t version,
                             const std::map<std::string, std::string>& chunks) {
  ByteWriter w;
  std::string head(kMagic, 8);
  std::string k = kind;
  k.resize(4, ' ');
  std::string out = head + k;
  w.put<std::uint32_t>(version);
  w.put<std::uint64_t>(chunks.size());
  for (const auto& [tag, bytes] : chunks) {
    w.put_string(tag);
    w.put_string(bytes);
  }
  out += w.take();
  const std::uint64_t sum = fnv1a64(out.data(), out.size());
  out.append(reinterpret_cast<const char*>(&sum), sizeof sum);
  return out;
}

const std::string& ChunkFile::at(const std::string& tag, const std::string& what) const {
  auto it = chunks.find(tag);
  if (it == chunks.end()) throw FileError(what + " has no '" + tag + "' section");
  return it->second;
}

ChunkFile read_chunk_file(const std::string& bytes, const std::string& kind, std::uint32_t max_version,
                          const std::string& what) {
  if (bytes.size() < 12 + 4 + 8 + 8 || bytes.compare(0, 8, std::string(kMagic, 8)) != 0)
    throw FileError(what + " is not a cellform file");
  std::string k = kind;
  k.resize(4, ' ');
  if (bytes.compare(8, 4, k) != 0)
    throw FileError(what + " is a cellform '" + printable(bytes.substr(8, 4)) + "' file, not a '" + kind + "' file");
  std::uint64_t stored;
  std::memcpy(&stored, bytes.data() + bytes.size() - 8, 8);
  if (fnv1a64(bytes.data(), bytes.size() - 8) != stored)
    throw FileError(what + " is corrupt (checksum mismatch: truncated or modified)");
  const std::string body = bytes.substr(12, bytes.size() - 12 - 8);
  ByteReader r(body, what);
  ChunkFile f;
  f.version = r.get<std::uint32_t>();
  if (f.version == 0 || f.version > max_version)
    throw FileError(what + " has format version " + std::to_string(f.version) + "; this cellform reads up to " +
                    std::to_string(max_version));
  const auto n = r.get<std::uint64_t>();
  for (std::uint64_t i = 0; i < n; ++i) {
    std::string tag = r.get_string();
    f.chunks[tag] = r.get_string();
  }
  if (!r.done()) throw FileError(what + " is corrupt (trailing data)");
  return f;
}

}  // namespace cellform::core
