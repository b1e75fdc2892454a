// Tests of the versioned checkpoint container.
#include "core/chunk_file.h"

#include <catch2/catch.hpp>

using namespace cellform::core;
using Catch::Matchers::Contains;
using Catch::Matchers::Equals;

TEST_CASE("chunk files round-trip and carry their version", "[core][checkpoint]") {
  ByteWriter w;
  w.put<double>(1.5);
  w.put_vector(std::vector<int>{1, 2, 3});
  w.put_string("abc");
  const std::string payload = w.take();
  const std::string file = write_chunk_file("CKPT", 3, {{"a", payload}, {"b", ""}});
  const ChunkFile f = read_chunk_file(file, "CKPT", 3, "test file");
  CHECK(f.version == 3);
  REQUIRE(f.chunks.size() == 2);
  ByteReader r(f.at("a", "test file"), "test file");
  CHECK(r.get<double>() == 1.5);
  CHECK(r.get_vector<int>() == std::vector<int>{1, 2, 3});
  CHECK(r.get_string() == "abc");
  CHECK(r.done());
  CHECK_THROWS_WITH(f.at("zzz", "test file"), Contains("has no 'zzz' section"));
}

TEST_CASE("corrupt, truncated, foreign and newer files are refused", "[core][checkpoint]") {
  const std::string file = write_chunk_file("CKPT", 1, {{"a", std::string(100, 'x')}});
  CHECK_THROWS_WITH(read_chunk_file(file.substr(0, 50), "CKPT", 1, "f"), Contains("corrupt"));
  for (std::size_t i = 0; i < file.size(); i += 7) {  // any flipped byte is caught
    std::string bad = file;
    bad[i] = static_cast<char>(bad[i] ^ 0x20);
    CHECK_THROWS_AS(read_chunk_file(bad, "CKPT", 1, "f"), FileError);
  }
  CHECK_THROWS_WITH(read_chunk_file("hello world, not a checkpoint at all", "CKPT", 1, "f"),
                    Contains("not a cellform file"));
  CHECK_THROWS_WITH(read_chunk_file(write_chunk_file("MESH", 1, {}), "CKPT", 1, "f"), Contains("not a 'CKPT' file"));
  // a kind of NUL or binary bytes is escaped: it cut the message ("is a cellform '") or wrote raw bytes
  std::string odd = write_chunk_file("CKPT", 1, {});
  odd.replace(8, 4, std::string("A\0\xff\x1b", 4));
  CHECK_THROWS_WITH(read_chunk_file(odd, "CKPT", 1, "f"),
                    Equals("f is a cellform 'A\\x00\\xff\\x1b' file, not a 'CKPT' file"));
  CHECK_THROWS_WITH(read_chunk_file(write_chunk_file("CKPT", 2, {}), "CKPT", 1, "f"), Contains("version 2"));
  const std::string short_string("\x05\x00\x00\x00\x00\x00\x00\x00", 8);  // says 5 bytes follow; none do
  ByteReader r(short_string, "f");
  CHECK_THROWS_WITH(r.get_string(), Contains("data ends early"));
}

TEST_CASE("bytes after the last chunk are refused as trailing data, even under a valid checksum",
          "[core][checkpoint]") {
  // a file is everything up to its checksum, then the FNV-1a checksum of those bytes (8 bytes, host order)
  const auto sealed = [](const std::string& body) {
    const std::uint64_t sum = fnv1a64(body.data(), body.size());
    return body + std::string(reinterpret_cast<const char*>(&sum), sizeof sum);
  };
  const std::string file = write_chunk_file("CKPT", 1, {{"a", "x"}});
  const std::string body = file.substr(0, file.size() - 8);
  REQUIRE(sealed(body) == file);  // sealed as the writer seals
  CHECK_THROWS_WITH(read_chunk_file(sealed(body + "junk"), "CKPT", 1, "f"), Equals("f is corrupt (trailing data)"));
  CHECK_THROWS_WITH(read_chunk_file(sealed(body + std::string(1, '\0')), "CKPT", 1, "f"), Contains("trailing data"));
  // a writer stating fewer chunks than it wrote: the record it did not count is trailing data
  const std::string two = write_chunk_file("CKPT", 1, {{"a", "x"}, {"b", "y"}});
  std::string undercounted = two.substr(0, two.size() - 8);
  const std::uint64_t one = 1;
  undercounted.replace(8 + 4 + 4, 8, reinterpret_cast<const char*>(&one), 8);  // magic, kind, version, count
  CHECK_THROWS_WITH(read_chunk_file(sealed(undercounted), "CKPT", 1, "f"), Contains("trailing data"));
}
