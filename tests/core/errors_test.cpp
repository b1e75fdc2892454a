// Message helpers of core/errors.h.
#include "core/errors.h"

#include <catch2/catch.hpp>
#include <new>
#include <stdexcept>

using cellform::core::error_text;

TEST_CASE("error_text says a failed allocation in words, and other errors as they are", "[core]") {
  const std::bad_alloc no_memory;
  CHECK(error_text(no_memory).rfind("out of memory: ", 0) == 0);
  CHECK(error_text(std::runtime_error("cannot open 'x'")) == "cannot open 'x'");
  CHECK(error_text(cellform::core::InvalidInput("cells.drag must be ...")) == "cells.drag must be ...");
}

TEST_CASE("number_text keeps messages short", "[core]") {
  CHECK(cellform::core::number_text(1e300) == "1e+300");
  CHECK(cellform::core::number_text(0.5) == "0.5");
  CHECK(cellform::core::point_text(0.5, -2, 1e300) == "{0.5, -2, 1e+300}");
  CHECK(cellform::core::number_text(-0.0) == "0");  // a sum of negative zeros, a rule's -0: no "-0"
  CHECK(cellform::core::number_text(-1e-300) == "-1e-300");
}

TEST_CASE("is_utf8 accepts well-formed UTF-8 (as JSON does) and nothing else", "[core]") {
  using cellform::core::is_utf8;
  CHECK(is_utf8(""));
  CHECK(is_utf8("leaf.lua"));
  CHECK(is_utf8("caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\x8c\xbf"));
  CHECK(is_utf8("\xc2\x85"));  // a C1 control is UTF-8 all the same
  CHECK(is_utf8(std::string("a\0b", 3)));
  CHECK_FALSE(is_utf8("n\xff\xfe"));         // never in UTF-8
  CHECK_FALSE(is_utf8("caf\xe9"));           // Latin-1
  CHECK_FALSE(is_utf8("\xc3"));              // cut short
  CHECK_FALSE(is_utf8("\xc0\xaf"));          // overlong
  CHECK_FALSE(is_utf8("\xed\xa0\x80"));      // a surrogate
  CHECK_FALSE(is_utf8("\xf4\x90\x80\x80"));  // beyond U+10FFFF
}

TEST_CASE("printable escapes the bytes that would act on a terminal or cut a message", "[core]") {
  using cellform::core::printable;
  CHECK(printable("leaf.obj: 'v 1 2'") == "leaf.obj: 'v 1 2'");
  CHECK(printable(std::string("a\x1b[2Jb", 6)) == "a\\x1b[2Jb");
  CHECK(printable(std::string("x\0y\n\x7f", 5)) == "x\\x00y\\x0a\\x7f");
  CHECK(printable("caf\xc3\xa9") == "caf\xc3\xa9");                                      // UTF-8 text stays
  CHECK(printable("\xe2\x82\xac \xf0\x9f\x8c\xbf") == "\xe2\x82\xac \xf0\x9f\x8c\xbf");  // 3 and 4 bytes
  // bytes outside well-formed UTF-8 are escaped: stray, cut short, overlong, a surrogate, beyond U+10FFFF
  CHECK(printable("uch\xe1r") == "uch\\xe1r");
  CHECK(printable("a\x80"
                  "b") == "a\\x80b");
  CHECK(printable("\xc3") == "\\xc3");
  CHECK(printable("\xc0\xaf") == "\\xc0\\xaf");
  CHECK(printable("\xed\xa0\x80") == "\\xed\\xa0\\x80");
  CHECK(printable("\xf4\x90\x80\x80") == "\\xf4\\x90\\x80\\x80");
  CHECK(printable("\xc2\x9b"
                  "2J") == "\\xc2\\x9b2J");    // U+009B, a terminal's CSI
  CHECK(printable("\xc2\xa0") == "\xc2\xa0");  // U+00A0, text
}

TEST_CASE("misspelt names are matched by edits and swaps; a name with nothing close gets no suggestion",
          "[core][errors]") {
  using cellform::core::closest_name;
  using cellform::core::edit_distance;
  CHECK(edit_distance("run", "rnu") == 1);  // a swap of neighbours is one edit
  CHECK(edit_distance("disc", "dsic") == 1);
  CHECK(edit_distance("kitten", "sitting") == 3);
  CHECK(edit_distance("", "abc") == 3);
  CHECK(edit_distance("abc", "abc") == 0);
  CHECK(edit_distance("ca", "abc") == 3);  // optimal string alignment: a swapped pair is not edited again
  const std::vector<std::string> fields{"type", "age", "generation", "id", "flow"};
  CHECK(closest_name("tpye", fields) == "type");
  CHECK(closest_name("nope", fields).empty());  // two of four letters changed: no "did you mean 'type'?"
  CHECK(closest_name("rnu", std::vector<std::string>{"run", "resume", "params", "check"}) == "run");
  CHECK(closest_name("seperation", std::vector<std::string>{"separation", "spring"}) == "separation");
  // letter case aside (PNG for png had no suggestion), and a name that begins another or that another begins
  const std::vector<std::string> output{"png", "png_size", "ply", "obj"};
  CHECK(closest_name("PNG", output) == "png");
  CHECK(closest_name("Png_Size", output) == "png_size");
  CHECK(closest_name("png", output) == "png");  // the name itself (as a name set to nil is recognised)
  const std::vector<std::string> sections{"print", "venation", "cells", "division", "output"};
  CHECK(closest_name("printing", sections) == "print");
  CHECK(closest_name("venationx", sections) == "venation");
  CHECK(closest_name("divisions", sections) == "division");
  CHECK(closest_name("pri", sections).empty());  // three letters are too few to go on
  CHECK(closest_name("outputting", sections) == "output");
  CHECK(closest_name("zzz", sections).empty());
  CHECK(closest_name("checkpoint", std::vector<std::string>{"run", "check"}).empty());  // half of it: no
  const std::vector<std::string> options{"--lua-instructions", "--lua-memory", "--lua-seconds"};
  CHECK(closest_name("--lua", options).empty());  // begins three: none picked
  // of two as close, the one that shares more of its beginning (both are two edits from "--steep")
  const std::vector<std::string> run{"--seed", "--steps", "--set"};
  CHECK(closest_name("--steep", run) == "--steps");
  CHECK(closest_name("--steep", std::vector<std::string>{"--steps", "--seed"}) == "--steps");  // in either order
  CHECK(closest_name("--sede", run) == "--seed");
}
