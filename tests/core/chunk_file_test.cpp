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
